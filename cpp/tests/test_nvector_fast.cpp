// pydrill::detail::make_fast_vector against NVECTOR_SERIAL: the vector's basics and the
// standard operations (see nvector_test_support.hpp for how they are compared). The fused and
// vector-array operations are in test_nvector_fast_arrays.cpp, whole CVODES runs in
// test_nvector_fast_cvodes.cpp.
#include <catch2/catch.hpp>

#include <sundials/sundials_config.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "nvector_test_support.hpp"

using namespace nvector_test;  // NOLINT(google-build-using-namespace): test helpers

TEST_CASE("fast vector basics", "[nvector_fast]") {
  Ctx c;
  VecPtr v(make_fast_vector(5, c.ctx));
  REQUIRE(v != nullptr);
  CHECK(is_fast_vector(v.get()));
  CHECK(N_VGetVectorID(v.get()) == SUNDIALS_NVEC_CUSTOM);
  CHECK(N_VGetLength(v.get()) == 5);
  CHECK(N_VGetArrayPointer(v.get()) == fast_vector_data(v.get()));
  for (int i = 0; i < 5; ++i) CHECK(fast_vector_data(v.get())[i] == 0.0);
  sunindextype lrw = -1, liw = -1;
  N_VSpace(v.get(), &lrw, &liw);
  CHECK(lrw == 5);
  CHECK(liw == 1);
#if SUNDIALS_VERSION_MAJOR >= 7
  CHECK(N_VGetCommunicator(v.get()) == SUN_COMM_NULL);
#else
  CHECK(N_VGetCommunicator(v.get()) == nullptr);
#endif

  // Clone: same ops and length, its own zeroed array.
  fast_vector_data(v.get())[2] = 7.0;
  VecPtr cl(N_VClone(v.get()));
  REQUIRE(cl != nullptr);
  CHECK(is_fast_vector(cl.get()));
  CHECK(N_VGetLength(cl.get()) == 5);
  CHECK(cl->sunctx == c.ctx);
  REQUIRE(fast_vector_data(cl.get()) != nullptr);
  CHECK(fast_vector_data(cl.get()) != fast_vector_data(v.get()));
  for (int i = 0; i < 5; ++i) CHECK(fast_vector_data(cl.get())[i] == 0.0);

  // Empty clone + set/get array pointer, the way CVODES' DQ Jacobian uses it.
  VecPtr em(N_VCloneEmpty(v.get()));
  REQUIRE(em != nullptr);
  CHECK(N_VGetLength(em.get()) == 5);
  CHECK(N_VGetArrayPointer(em.get()) == nullptr);
  double user[5] = {1, 2, 3, 4, 5};
  N_VSetArrayPointer(user, em.get());
  CHECK(N_VGetArrayPointer(em.get()) == user);
  N_VScale(2.0, em.get(), em.get());
  CHECK(user[4] == 10.0);
  em.reset();  // must not free `user`

  // Re-pointing a vector that owns an array: the owned array is kept (and
  // freed on destroy), the user array is never freed.
  double* own = fast_vector_data(cl.get());
  N_VSetArrayPointer(user, cl.get());
  CHECK(N_VGetArrayPointer(cl.get()) == user);
  N_VSetArrayPointer(own, cl.get());
  CHECK(N_VGetArrayPointer(cl.get()) == own);

  // Zero length.
  VecPtr z0(make_fast_vector(0, c.ctx));
  REQUIRE(z0 != nullptr);
  CHECK(N_VGetLength(z0.get()) == 0);
  CHECK(fast_vector_data(z0.get()) == nullptr);
  VecPtr z0c(N_VClone(z0.get()));
  REQUIRE(z0c != nullptr);
  CHECK(N_VDotProd(z0.get(), z0c.get()) == 0.0);

  CHECK(make_fast_vector(-1, c.ctx) == nullptr);
  N_VDestroy(nullptr);  // tolerated by the generic wrapper

  VecPtr s(N_VNew_Serial(3, c.ctx));
  CHECK_FALSE(is_fast_vector(s.get()));
  CHECK_FALSE(is_fast_vector(nullptr));

  // XBraid buffer ops round-trip.
  sunindextype size = 0;
  REQUIRE(N_VBufSize(v.get(), &size) == 0);
  CHECK(size == static_cast<sunindextype>(5 * sizeof(double)));
  std::vector<double> buf(5);
  REQUIRE(N_VBufPack(v.get(), buf.data()) == 0);
  CHECK(buf[2] == 7.0);
  buf[3] = -1.5;
  REQUIRE(N_VBufUnpack(cl.get(), buf.data()) == 0);
  CHECK(fast_vector_data(cl.get())[3] == -1.5);

  // Fused operations reject nvec < 1 like NVECTOR_SERIAL.
  N_Vector arr[1] = {v.get()};
  double cc[1] = {1.0};
  CHECK(N_VLinearCombination(0, cc, arr, v.get()) != 0);
}

TEST_CASE("fast vector standard operations match NVECTOR_SERIAL", "[nvector_fast]") {
  Ctx c;
  const sunindextype n = GENERATE(as<sunindextype>{}, 1, 7, 1000);
  std::mt19937_64 rng(12345 + static_cast<unsigned>(n));
  World w(c.ctx, n, 4);

  auto fresh = [&] { w.randomise(rng); };

  SECTION("LinearSum, all coefficient cases and aliasing patterns") {
    for (const auto& [a, b] : kLinSumCoeffs) {
      for (const auto& p : kXYZ) {
        fresh();
        check_op(w,
                 "LinearSum a=" + std::to_string(a) + " b=" + std::to_string(b) + " x,y,z=" +
                     std::to_string(p[0]) + std::to_string(p[1]) + std::to_string(p[2]),
                 [&, a = a, b = b](const Getter& g) {
                   N_VLinearSum(a, g(p[0]), b, g(p[1]), g(p[2]));
                   return std::vector<Scalar>{};
                 });
      }
    }
  }

  SECTION("Const") {
    fresh();
    check_op(w, "Const", [](const Getter& g) {
      N_VConst(3.25, g(0));
      return std::vector<Scalar>{};
    });
  }

  SECTION("Prod, Div") {
    for (const auto& p : kXYZ) {
      fresh();
      check_op(w, "Prod", [&](const Getter& g) {
        N_VProd(g(p[0]), g(p[1]), g(p[2]));
        return std::vector<Scalar>{};
      });
      fresh();
      check_op(w, "Div", [&](const Getter& g) {
        N_VDiv(g(p[0]), g(p[1]), g(p[2]));
        return std::vector<Scalar>{};
      });
    }
  }

  SECTION("Scale, Abs, Inv, AddConst, Compare (z distinct and z == x)") {
    for (int zi : {1, 0}) {
      for (double cs : {1.0, -1.0, 2.5, 0.0}) {
        fresh();
        check_op(w, "Scale c=" + std::to_string(cs), [&](const Getter& g) {
          N_VScale(cs, g(0), g(zi));
          return std::vector<Scalar>{};
        });
      }
      fresh();
      check_op(w, "Abs", [&](const Getter& g) {
        N_VAbs(g(0), g(zi));
        return std::vector<Scalar>{};
      });
      fresh();
      check_op(w, "Inv", [&](const Getter& g) {
        N_VInv(g(0), g(zi));
        return std::vector<Scalar>{};
      });
      fresh();
      check_op(w, "AddConst", [&](const Getter& g) {
        N_VAddConst(g(0), -0.75, g(zi));
        return std::vector<Scalar>{};
      });
      fresh();
      check_op(w, "Compare", [&](const Getter& g) {
        N_VCompare(1.0, g(0), g(zi));  // |x| in [0.5, 2]: both outcomes occur
        return std::vector<Scalar>{};
      });
    }
  }

  SECTION("Reductions and their local variants") {
    fresh();
    for (int l = 1; l < 4; ++l) w.set(2, (l * 37) % n, 0.0);  // masked-out entries in id = v2
    w.set(2, 0, -1.0);
    for (int yi : {1, 0}) {
      const double ds = abs_dot(w.serial(0), w.serial(yi));
      check_op(w, "DotProd", [&](const Getter& g) {
        return std::vector<Scalar>{{N_VDotProd(g(0), g(yi)), ds}, {N_VDotProdLocal(g(0), g(yi)), ds}};
      });
    }
    check_op(w, "MaxNorm/Min/L1Norm", [](const Getter& g) {
      return std::vector<Scalar>{{N_VMaxNorm(g(0))}, {N_VMaxNormLocal(g(0))}, {N_VMin(g(0))},
                                 {N_VMinLocal(g(0))}, {N_VL1Norm(g(0))}, {N_VL1NormLocal(g(0))}};
    });
    check_op(w, "WrmsNorm/WL2Norm/WSqrSum", [](const Getter& g) {
      return std::vector<Scalar>{{N_VWrmsNorm(g(0), g(1))},
                                 {N_VWL2Norm(g(0), g(1))},
                                 {N_VWSqrSumLocal(g(0), g(1))},
                                 {N_VWrmsNorm(g(0), g(0))}};
    });
    check_op(w, "WrmsNormMask/WSqrSumMask", [](const Getter& g) {
      return std::vector<Scalar>{{N_VWrmsNormMask(g(0), g(1), g(2))},
                                 {N_VWSqrSumMaskLocal(g(0), g(1), g(2))}};
    });
    // An all-positive vector for Min (no sign shortcuts) and one with its
    // minimum in the last element.
    for (sunindextype j = 0; j < n; ++j) w.set(3, j, 10.0 - 1e-3 * static_cast<double>(j));
    check_op(w, "Min decreasing", [](const Getter& g) {
      return std::vector<Scalar>{{N_VMin(g(3))}, {N_VMaxNorm(g(3))}};
    });
  }

  SECTION("InvTest") {
    for (int zi : {1, 0}) {
      fresh();
      check_op(w, "InvTest no zeros", [&](const Getter& g) {
        return std::vector<Scalar>{{static_cast<double>(N_VInvTest(g(0), g(zi)))},
                                   {static_cast<double>(N_VInvTestLocal(g(0), g(zi)))}};
      });
      fresh();
      w.set(0, n / 2, 0.0);
      w.set(0, n - 1, 0.0);
      check_op(w, "InvTest with zeros", [&](const Getter& g) {
        return std::vector<Scalar>{{static_cast<double>(N_VInvTest(g(0), g(zi)))}};
      });
    }
  }

  SECTION("ConstrMask") {
    // constraints in {-2,-1,0,1,2}, x with random signs and some zeros
    std::uniform_int_distribution<int> cdist(-2, 2);
    for (const auto& p : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 1, 1}, {0, 1, 0}}) {
      fresh();
      for (sunindextype j = 0; j < n; ++j) {
        w.set(0, j, cdist(rng));
        if (j % 5 == 3) w.set(1, j, 0.0);
      }
      check_op(w, "ConstrMask c,x,m=" + std::to_string(p[0]) + std::to_string(p[1]) + std::to_string(p[2]),
               [&](const Getter& g) {
                 return std::vector<Scalar>{
                     {static_cast<double>(N_VConstrMask(g(p[0]), g(p[1]), g(p[2])))}};
               });
    }
    // all constraints satisfied
    fresh();
    for (sunindextype j = 0; j < n; ++j) {
      w.set(0, j, 2.0);
      w.set(1, j, 1.0 + static_cast<double>(j));
    }
    check_op(w, "ConstrMask satisfied", [](const Getter& g) {
      return std::vector<Scalar>{{static_cast<double>(N_VConstrMaskLocal(g(0), g(1), g(2)))}};
    });
  }

  SECTION("MinQuotient") {
    fresh();
    for (sunindextype j = 0; j < n; j += 3) w.set(1, j, 0.0);
    check_op(w, "MinQuotient", [](const Getter& g) {
      return std::vector<Scalar>{{N_VMinQuotient(g(0), g(1))}, {N_VMinQuotientLocal(g(0), g(1))}};
    });
    for (sunindextype j = 0; j < n; ++j) w.set(1, j, 0.0);
    check_op(w, "MinQuotient all zero denominators", [](const Getter& g) {
      return std::vector<Scalar>{{N_VMinQuotient(g(0), g(1))}};
    });
  }
}
