// PYDRILL_API marks the declarations libpydrill exports. The library is compiled with
// -fvisibility=hidden and -fvisibility-inlines-hidden: everything else (the integrators, the
// banded solvers, the regime judge, Eigen's templates) stays inside it, so a shared
// libpydrill exports its public API alone, and a static one linked into a program's own
// shared library (as into the Python module) adds nothing to that library's exports — no
// Eigen instantiation of pydrill's to clash with the program's own Eigen.
//
// CMake sets the macros: PYDRILL_STATIC for a static libpydrill (its users get it through
// the target pydrill::pydrill), PYDRILL_BUILDING while the library itself is compiled. A
// build by hand against a static libpydrill defines PYDRILL_STATIC itself.
#pragma once

#if defined(PYDRILL_STATIC)
#define PYDRILL_API
#elif defined(_WIN32) || defined(__CYGWIN__)
#if defined(PYDRILL_BUILDING)
#define PYDRILL_API __declspec(dllexport)
#else
#define PYDRILL_API __declspec(dllimport)
#endif
#else
#define PYDRILL_API __attribute__((visibility("default")))
#endif
