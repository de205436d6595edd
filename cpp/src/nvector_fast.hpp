// A serial N_Vector compiled with this project's optimisation flags.
//
// Debian's SUNDIALS is built without optimisation, so NVECTOR_SERIAL's
// kernels (the loops CVODES spends most of its non-RHS time in) run 3-10x
// slower than they should. This is a drop-in replacement: one contiguous
// array per vector, every operation CVODES uses, with the same results as
// NVECTOR_SERIAL -- element-wise operations reproduce its arithmetic (and its
// special cases and in-place/aliasing behaviour) exactly; reductions (dot
// products, norms) differ only in summation order, i.e. by rounding (see
// fast_vector_exact_reductions).
//
// The vector reports SUNDIALS_NVEC_CUSTOM. SUNDIALS' own dense, band, KLU and
// LAPACK linear solvers refuse such vectors at construction (they accept
// only SERIAL/OPENMP/PTHREADS IDs); the iterative solvers (SPGMR, ...), the
// Newton and fixed-point nonlinear solvers and matrix-free or custom
// matrix-embedded linear solvers work with it.
#pragma once

#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_nvector.h>
#include <sundials/sundials_types.h>

namespace pydrill::detail {

// A new vector of `length` elements, all zero, owning its storage.
// Returns nullptr if length < 0 or allocation fails. Free with N_VDestroy.
N_Vector make_fast_vector(sunindextype length, SUNContext ctx);

// The data array of a vector made by make_fast_vector (or cloned from one);
// nullptr for a zero-length vector or an empty clone.
sunrealtype* fast_vector_data(N_Vector v);

// True if `v` is one of ours (made by make_fast_vector or cloned from one).
bool is_fast_vector(N_Vector v);

// By default sums (dot products, norms) use several partial sums, which is
// faster but rounds differently from NVECTOR_SERIAL's sequential sum. Built
// with PYDRILL_NVEC_EXACT_REDUCTIONS defined, they sum sequentially and every
// operation is bit-identical to NVECTOR_SERIAL (on the same compiler flags
// as far as FMA contraction goes). Reports which variant was compiled.
bool fast_vector_exact_reductions();

// True if new vectors use the operations compiled for AVX2 (the CPU has it and the build made
// them): the same results, twice the width.
bool fast_vector_uses_avx2();

}  // namespace pydrill::detail
