// The N_Vector the simulator integrates with, and owning handles for the
// SUNDIALS objects. Our own serial vector, compiled with optimisation,
// replaces NVECTOR_SERIAL: Debian builds SUNDIALS without optimisation, and
// vector operations are most of the integrators' O(n) work.
#pragma once

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_nonlinearsolver.h>

#include <memory>
#include <type_traits>

#include "nvector_fast.hpp"

namespace pydrill::detail {

inline N_Vector make_vector(int n, SUNContext ctx) { return make_fast_vector(n, ctx); }

struct VectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct LinearSolverDeleter {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
struct NonlinearSolverDeleter {
  void operator()(SUNNonlinearSolver s) const { SUNNonlinSolFree(s); }
};
using VectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using LinearSolverPtr = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;
using NonlinearSolverPtr =
    std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinearSolverDeleter>;

}  // namespace pydrill::detail
