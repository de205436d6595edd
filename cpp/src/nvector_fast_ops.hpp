// The fast N_Vector's operations, one variant's (see nvector_fast_kernels.hpp): the functions
// its ops table points at. Each family is defined in its own file -- element-wise
// (nvector_fast_elementwise.cpp), reductions (nvector_fast_reductions.cpp), the constraint
// operations (nvector_fast_constraints.cpp), fused and vector-array operations
// (nvector_fast_arrays.cpp), and construction, buffers and the table itself (nvector_fast.cpp).
// They have external linkage so the table can name them across files, and live in their
// variant's namespace (generic or avx2), so the AVX2 build's copies never share a name (nor
// a weak symbol the linker could pick for the plain build) with the plain ones.
#pragma once

#include <cstdio>

#include "nvector_fast_kernels.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {

// construction, destruction, utility (nvector_fast.cpp)
N_Vector_ID op_getvectorid(N_Vector v) noexcept;
sunindextype op_getlength(N_Vector v) noexcept;
N_Vector op_clone(N_Vector w) noexcept;
N_Vector op_cloneempty(N_Vector w) noexcept;
void op_destroy(N_Vector v) noexcept;
void op_space(N_Vector v, sunindextype* lrw, sunindextype* liw) noexcept;
sunrealtype* op_getarraypointer(N_Vector v) noexcept;
void op_setarraypointer(sunrealtype* v_data, N_Vector v) noexcept;

// element-wise (nvector_fast_elementwise.cpp)
void op_linearsum(real a, N_Vector x, real b, N_Vector y, N_Vector z) noexcept;
void op_const(real c, N_Vector z) noexcept;
void op_prod(N_Vector x, N_Vector y, N_Vector z) noexcept;
void op_div(N_Vector x, N_Vector y, N_Vector z) noexcept;
void op_scale(real c, N_Vector x, N_Vector z) noexcept;
void op_abs(N_Vector x, N_Vector z) noexcept;
void op_inv(N_Vector x, N_Vector z) noexcept;
void op_addconst(N_Vector x, real b, N_Vector z) noexcept;
void op_compare(real c, N_Vector x, N_Vector z) noexcept;

// reductions (nvector_fast_reductions.cpp)
real op_dotprod(N_Vector x, N_Vector y) noexcept;
real op_maxnorm(N_Vector x) noexcept;
real op_wsqrsumlocal(N_Vector x, N_Vector w) noexcept;
real op_wsqrsummasklocal(N_Vector x, N_Vector w, N_Vector id) noexcept;
real op_wrmsnorm(N_Vector x, N_Vector w) noexcept;
real op_wrmsnormmask(N_Vector x, N_Vector w, N_Vector id) noexcept;
real op_min(N_Vector x) noexcept;
real op_wl2norm(N_Vector x, N_Vector w) noexcept;
real op_l1norm(N_Vector x) noexcept;

// inequality constraints (nvector_fast_constraints.cpp)
sunbooleantype op_invtest(N_Vector x, N_Vector z) noexcept;
sunbooleantype op_constrmask(N_Vector c, N_Vector x, N_Vector m) noexcept;
real op_minquotient(N_Vector num, N_Vector denom) noexcept;

// fused and vector-array operations (nvector_fast_arrays.cpp)
err_t op_linearcombination(int nvec, real* c, N_Vector* X, N_Vector z) noexcept;
err_t op_scaleaddmulti(int nvec, real* a, N_Vector x, N_Vector* Y, N_Vector* Z) noexcept;
err_t op_dotprodmulti(int nvec, N_Vector x, N_Vector* Y, real* dotprods) noexcept;
err_t op_linearsumvectorarray(int nvec, real a, N_Vector* X, real b, N_Vector* Y,
                              N_Vector* Z) noexcept;
err_t op_scalevectorarray(int nvec, real* c, N_Vector* X, N_Vector* Z) noexcept;
err_t op_constvectorarray(int nvec, real c, N_Vector* Z) noexcept;
err_t op_wrmsnormvectorarray(int nvec, N_Vector* X, N_Vector* W, real* nrm) noexcept;
err_t op_wrmsnormmaskvectorarray(int nvec, N_Vector* X, N_Vector* W, N_Vector id,
                                 real* nrm) noexcept;
err_t op_scaleaddmultivectorarray(int nvec, int nsum, real* a, N_Vector* X, N_Vector** Y,
                                  N_Vector** Z) noexcept;
err_t op_linearcombinationvectorarray(int nvec, int nsum, real* c, N_Vector** X,
                                      N_Vector* Z) noexcept;

// XBraid buffers and printing (nvector_fast.cpp)
err_t op_bufsize(N_Vector x, sunindextype* size) noexcept;
err_t op_bufpack(N_Vector x, void* buf) noexcept;
err_t op_bufunpack(N_Vector x, void* buf) noexcept;
void op_printfile(N_Vector x, FILE* out) noexcept;
void op_print(N_Vector x) noexcept;

// This variant's operations, and whether a vector has them (their ID function tells).
void attach(N_Vector_Ops ops) noexcept;
bool owns(N_Vector v) noexcept;

}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
