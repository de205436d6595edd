// Optimised serial N_Vector; see nvector_fast.hpp for what and why, and nvector_fast_kernels.hpp
// for how its loops are written. This file: construction, cloning and destruction, the
// buffer and print operations, the ops table that names every operation (defined by family in
// nvector_fast_*.cpp, declared in nvector_fast_ops.hpp), and make_fast_vector, which picks the
// plain or the AVX2 table (nvector_fast_avx2.cpp) by CPU.
#include "nvector_fast.hpp"

#include <cstdio>
#include <new>

#include "nvector_fast_ops.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {

N_Vector_ID op_getvectorid(N_Vector) noexcept { return SUNDIALS_NVEC_CUSTOM; }

sunindextype op_getlength(N_Vector v) noexcept { return len(v); }

N_Vector op_clone(N_Vector w) noexcept {
  N_Vector v = op_cloneempty(w);
  if (v == nullptr) return nullptr;
  const index_t n = len(w);
  if (n > 0) {
    real* data = new (std::nothrow) real[static_cast<size_t>(n)]();
    if (data == nullptr) {
      op_destroy(v);
      return nullptr;
    }
    content(v)->owned = data;
    content(v)->data = data;
  }
  return v;
}

N_Vector op_cloneempty(N_Vector w) noexcept {
  if (w == nullptr) return nullptr;
  N_Vector v = N_VNewEmpty(w->sunctx);
  if (v == nullptr) return nullptr;
  if (N_VCopyOps(w, v) != 0) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  auto* c = new (std::nothrow) Content;
  if (c == nullptr) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  c->length = len(w);
  v->content = c;
  return v;
}

void op_destroy(N_Vector v) noexcept {
  if (v == nullptr) return;
  if (v->content != nullptr) {
    Content* c = content(v);
    delete[] c->owned;
    delete c;
    v->content = nullptr;
  }
  N_VFreeEmpty(v);  // frees the ops table and the vector struct
}

void op_space(N_Vector v, sunindextype* lrw, sunindextype* liw) noexcept {
  if (lrw != nullptr) *lrw = len(v);
  if (liw != nullptr) *liw = 1;
}

sunrealtype* op_getarraypointer(N_Vector v) noexcept { return dat(v); }

// Like NVECTOR_SERIAL: ignored for zero-length vectors; never frees anything
// (our own array, if any, is released on destroy).
void op_setarraypointer(sunrealtype* v_data, N_Vector v) noexcept {
  if (len(v) > 0) content(v)->data = v_data;
}

// ---- XBraid buffer operations and printing (cheap to provide) ---------------

err_t op_bufsize(N_Vector x, sunindextype* size) noexcept {
  *size = len(x) * static_cast<sunindextype>(sizeof(real));
  return kSuccess;
}

err_t op_bufpack(N_Vector x, void* buf) noexcept {
  if (buf == nullptr) return kBadArg;
  map1(len(x), dat(x), static_cast<real*>(buf), [](real a) { return a; });
  return kSuccess;
}

err_t op_bufunpack(N_Vector x, void* buf) noexcept {
  if (buf == nullptr) return kBadArg;
  map1(len(x), static_cast<const real*>(buf), dat(x), [](real a) { return a; });
  return kSuccess;
}

void op_printfile(N_Vector x, FILE* out) noexcept {
  const index_t n = len(x);
  const real* xd = dat(x);
  for (index_t i = 0; i < n; ++i) {
    std::fprintf(out, "%.17Lg\n", static_cast<long double>(xd[i]));
  }
}

void op_print(N_Vector x) noexcept { op_printfile(x, stdout); }

namespace {

void attach_ops(N_Vector_Ops ops) noexcept {
  // constructors, destructors, utility
  ops->nvgetvectorid = op_getvectorid;
  ops->nvclone = op_clone;
  ops->nvcloneempty = op_cloneempty;
  ops->nvdestroy = op_destroy;
  ops->nvspace = op_space;
  ops->nvgetarraypointer = op_getarraypointer;
  ops->nvsetarraypointer = op_setarraypointer;
  ops->nvgetlength = op_getlength;
  ops->nvgetlocallength = op_getlength;
  // nvgetcommunicator stays NULL: N_VGetCommunicator then reports "none".

  // standard operations
  ops->nvlinearsum = op_linearsum;
  ops->nvconst = op_const;
  ops->nvprod = op_prod;
  ops->nvdiv = op_div;
  ops->nvscale = op_scale;
  ops->nvabs = op_abs;
  ops->nvinv = op_inv;
  ops->nvaddconst = op_addconst;
  ops->nvdotprod = op_dotprod;
  ops->nvmaxnorm = op_maxnorm;
  ops->nvwrmsnorm = op_wrmsnorm;
  ops->nvwrmsnormmask = op_wrmsnormmask;
  ops->nvmin = op_min;
  ops->nvwl2norm = op_wl2norm;
  ops->nvl1norm = op_l1norm;
  ops->nvcompare = op_compare;
  ops->nvinvtest = op_invtest;
  ops->nvconstrmask = op_constrmask;
  ops->nvminquotient = op_minquotient;

  // fused operations (CVODES prefers them when present)
  ops->nvlinearcombination = op_linearcombination;
  ops->nvscaleaddmulti = op_scaleaddmulti;
  ops->nvdotprodmulti = op_dotprodmulti;

  // vector array operations
  ops->nvlinearsumvectorarray = op_linearsumvectorarray;
  ops->nvscalevectorarray = op_scalevectorarray;
  ops->nvconstvectorarray = op_constvectorarray;
  ops->nvwrmsnormvectorarray = op_wrmsnormvectorarray;
  ops->nvwrmsnormmaskvectorarray = op_wrmsnormmaskvectorarray;
  ops->nvscaleaddmultivectorarray = op_scaleaddmultivectorarray;
  ops->nvlinearcombinationvectorarray = op_linearcombinationvectorarray;

  // local reductions: serial, so identical to the global ones
  ops->nvdotprodlocal = op_dotprod;
  ops->nvmaxnormlocal = op_maxnorm;
  ops->nvminlocal = op_min;
  ops->nvl1normlocal = op_l1norm;
  ops->nvinvtestlocal = op_invtest;
  ops->nvconstrmasklocal = op_constrmask;
  ops->nvminquotientlocal = op_minquotient;
  ops->nvwsqrsumlocal = op_wsqrsumlocal;
  ops->nvwsqrsummasklocal = op_wsqrsummasklocal;
  ops->nvdotprodmultilocal = op_dotprodmulti;

  // XBraid interface, debugging
  ops->nvbufsize = op_bufsize;
  ops->nvbufpack = op_bufpack;
  ops->nvbufunpack = op_bufunpack;
  ops->nvprint = op_print;
  ops->nvprintfile = op_printfile;
}

}  // namespace

// This variant's operations, and whether a vector has them (their ID function tells).
void attach(N_Vector_Ops ops) noexcept { attach_ops(ops); }
bool owns(N_Vector v) noexcept { return v->ops->nvgetvectorid == op_getvectorid; }

}  // namespace PYDRILL_NVEC_VARIANT

#ifdef PYDRILL_NVEC_MAIN
#ifdef PYDRILL_NVEC_AVX2
namespace avx2 {
void attach(N_Vector_Ops ops) noexcept;
bool owns(N_Vector v) noexcept;
}  // namespace avx2
#endif

namespace {
using namespace generic;

bool has_avx2() {
#ifdef PYDRILL_NVEC_AVX2
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
#else
  return false;
#endif
}
}  // namespace

N_Vector make_fast_vector(sunindextype length, SUNContext ctx) {
  if (length < 0) return nullptr;
  N_Vector v = N_VNewEmpty(ctx);
  if (v == nullptr) return nullptr;
#ifdef PYDRILL_NVEC_AVX2
  if (has_avx2()) {
    avx2::attach(v->ops);
  } else {
    attach_ops(v->ops);
  }
#else
  attach_ops(v->ops);
#endif
  auto* c = new (std::nothrow) Content;
  if (c == nullptr) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  c->length = length;
  v->content = c;
  if (length > 0) {
    real* data = new (std::nothrow) real[static_cast<size_t>(length)]();  // () zero-initialises
    if (data == nullptr) {
      op_destroy(v);
      return nullptr;
    }
    c->owned = data;
    c->data = data;
  }
  return v;
}

sunrealtype* fast_vector_data(N_Vector v) { return dat(v); }

bool fast_vector_exact_reductions() { return kLanes == 1; }

bool is_fast_vector(N_Vector v) {
  if (v == nullptr || v->ops == nullptr || v->content == nullptr) return false;
#ifdef PYDRILL_NVEC_AVX2
  if (avx2::owns(v)) return true;
#endif
  return generic::owns(v);
}

bool fast_vector_uses_avx2() { return has_avx2(); }
#endif  // PYDRILL_NVEC_MAIN

}  // namespace pydrill::detail
