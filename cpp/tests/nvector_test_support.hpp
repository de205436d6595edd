// What the fast N_Vector's tests share (test_nvector_fast*.cpp): a SUNDIALS context, owned
// vectors, the comparison to 1e-14, and the two "worlds" of vectors -- NVECTOR_SERIAL's
// (fused operations enabled, so the serial fused kernels are the reference) and fast ones --
// holding identical random data, on which every operation is applied with the same vector
// indices, so aliasing patterns (z == x, Z == Y, ...) are reproduced exactly. Afterwards every
// vector and every returned scalar must agree to 1e-14 (relative, see `close`).
#pragma once

#include <catch2/catch.hpp>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <memory>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "nvector_fast.hpp"

namespace nvector_test {

using pydrill::detail::fast_vector_data;
using pydrill::detail::is_fast_vector;
using pydrill::detail::make_fast_vector;

inline constexpr double kTol = 1e-14;

struct Ctx {
  SUNContext ctx = nullptr;
  Ctx() {
#if SUNDIALS_VERSION_MAJOR >= 7
    SUNContext_Create(SUN_COMM_NULL, &ctx);
#else
    SUNContext_Create(nullptr, &ctx);
#endif
  }
  ~Ctx() { SUNContext_Free(&ctx); }
  Ctx(const Ctx&) = delete;
  Ctx& operator=(const Ctx&) = delete;
};

struct VecDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
using VecPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VecDeleter>;

inline VecPtr make_serial(sunindextype n, SUNContext ctx, bool fused = true) {
  N_Vector v = N_VNew_Serial(n, ctx);
  if (fused) N_VEnableFusedOps_Serial(v, SUNTRUE);
  return VecPtr(v);
}

// |got - ref| <= tol * max(|ref|, scale). `scale` is the magnitude of the
// terms that produced ref (1 for our O(1) data; sum |x_i y_i| for dot
// products, whose result may cancel to near 0).
inline bool close(double got, double ref, double scale = 1.0, double tol = kTol) {
  if (got == ref) return true;  // also covers matching infinities
  if (std::isnan(got) || std::isnan(ref)) return std::isnan(got) && std::isnan(ref);
  return std::fabs(got - ref) <= tol * std::max(std::fabs(ref), scale);
}

struct Scalar {
  double value;
  double scale = 1.0;
};

// Two parallel sets of vectors with identical contents.
class World {
 public:
  World(SUNContext ctx, sunindextype n, int count) : n_(n) {
    for (int i = 0; i < count; ++i) {
      s_.push_back(make_serial(n, ctx));
      VecPtr f(make_fast_vector(n, ctx));
      REQUIRE(f != nullptr);
      f_.push_back(std::move(f));
    }
  }
  sunindextype n() const { return n_; }
  int count() const { return static_cast<int>(s_.size()); }
  N_Vector serial(int i) const { return s_.at(static_cast<size_t>(i)).get(); }
  N_Vector fast(int i) const { return f_.at(static_cast<size_t>(i)).get(); }

  // Sets element j of vector i in both worlds.
  void set(int i, sunindextype j, double v) {
    N_VGetArrayPointer(serial(i))[j] = v;
    fast_vector_data(fast(i))[j] = v;
  }
  double get_serial(int i, sunindextype j) const { return N_VGetArrayPointer(serial(i))[j]; }

  // Random values with |v| in [0.5, 2] and random sign: O(1), never near 0,
  // so quotients and inverses stay O(1) too.
  void randomise(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> mag(0.5, 2.0);
    std::bernoulli_distribution neg(0.5);
    for (int i = 0; i < count(); ++i) {
      for (sunindextype j = 0; j < n_; ++j) set(i, j, neg(rng) ? -mag(rng) : mag(rng));
    }
  }

  // Every element of every vector must agree.
  void require_equal(const std::string& what) const {
    for (int i = 0; i < count(); ++i) {
      const double* s = N_VGetArrayPointer(serial(i));
      const double* f = fast_vector_data(fast(i));
      for (sunindextype j = 0; j < n_; ++j) {
        if (!close(f[j], s[j])) {
          FAIL_CHECK(what << ": vector " << i << " element " << j << " (n=" << n_ << "): fast "
                          << f[j] << " vs serial " << s[j]);
          return;
        }
      }
    }
  }

 private:
  sunindextype n_;
  std::vector<VecPtr> s_, f_;
};

using Getter = std::function<N_Vector(int)>;
using Op = std::function<std::vector<Scalar>(const Getter&)>;

// Applies `op` to both worlds and compares vectors and returned scalars.
inline void check_op(World& w, const std::string& what, const Op& op) {
  const std::vector<Scalar> rs = op([&w](int i) { return w.serial(i); });
  const std::vector<Scalar> rf = op([&w](int i) { return w.fast(i); });
  REQUIRE(rs.size() == rf.size());
  for (size_t k = 0; k < rs.size(); ++k) {
    INFO(what << ": scalar result " << k << " (n=" << w.n() << "): fast " << rf[k].value
              << " vs serial " << rs[k].value);
    CHECK(close(rf[k].value, rs[k].value, rs[k].scale));
  }
  w.require_equal(what);
}

inline std::vector<N_Vector> vecs(const Getter& g, std::initializer_list<int> idx) {
  std::vector<N_Vector> out;
  for (int i : idx) out.push_back(g(i));
  return out;
}

// sum_i |x_i y_i| on the serial copy: the natural scale of a dot product.
inline double abs_dot(N_Vector x, N_Vector y) {
  const sunindextype n = N_VGetLength(x);
  const double* a = N_VGetArrayPointer(x);
  const double* b = N_VGetArrayPointer(y);
  double s = 0;
  for (sunindextype i = 0; i < n; ++i) s += std::fabs(a[i] * b[i]);
  return s;
}

// Coefficient pairs hitting every branch of NVECTOR_SERIAL's N_VLinearSum.
inline const std::vector<std::pair<double, double>> kLinSumCoeffs = {
    {1.0, 1.0},  {1.0, -1.0}, {-1.0, 1.0}, {-1.0, -1.0}, {1.0, 2.5},  {2.5, 1.0},  {-1.0, 2.5},
    {2.5, -1.0}, {2.5, 2.5},  {2.5, -2.5}, {2.5, 0.7},   {0.0, 0.0},  {0.0, 3.0},  {3.0, 0.0},
    {1.0, 0.0},  {0.0, 1.0},  {-0.3, 0.3}};

// (x, y, z) index patterns: distinct, z == x, z == y, x == y, all equal.
inline const std::vector<std::array<int, 3>> kXYZ = {{0, 1, 2}, {0, 1, 0}, {0, 1, 1}, {0, 0, 2}, {0, 0, 0}};

}  // namespace nvector_test
