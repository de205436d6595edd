// FlushSubnormals: a simulation's floating-point setting (subnormals flushed to zero), and
// the caller's restored around the caller's own code. Used by simulator.cpp's run loop.
#pragma once

#include <functional>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#define PYDRILL_HAVE_MXCSR 1
#endif

namespace pydrill::detail {

// Subnormal numbers flushed to zero while a simulation runs (this thread only,
// restored after). A string started from rest winds up from its top: ahead of
// the torsional wave the states are exponentially small, and arithmetic on
// subnormals costs ~100x: measured, 200 pipes from rest ran 2x slower per step
// than from equilibrium. Nothing below 2e-308 matters at any tolerance.
// The caller's own code — options.interrupt, which a program that embeds pydrill may use to
// run its event loop, and Python's signal handlers — runs with the caller's setting: see
// ask().
class FlushSubnormals {
 public:
#ifdef PYDRILL_HAVE_MXCSR
  FlushSubnormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040); }  // FTZ | DAZ
  ~FlushSubnormals() { _mm_setcsr(saved_); }
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;
#endif

  // interrupt() under the caller's floating-point setting, ours again after it (or after an
  // exception from it). It ran with subnormals flushed: a callback's arithmetic on numbers
  // below 2e-308 silently gave 0 there.
  bool ask(const std::function<bool()>& interrupt) const {
#ifdef PYDRILL_HAVE_MXCSR
    struct Caller {
      unsigned ours;
      explicit Caller(unsigned theirs) : ours(_mm_getcsr()) { _mm_setcsr(theirs); }
      ~Caller() { _mm_setcsr(ours); }
    } caller(saved_);
#endif
    return interrupt();
  }

#ifdef PYDRILL_HAVE_MXCSR
 private:
  unsigned saved_;
#endif
};

}  // namespace pydrill::detail
