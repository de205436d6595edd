// The fast N_Vector's fused and vector-array operations against NVECTOR_SERIAL's (see
// nvector_test_support.hpp for how they are compared).
#include <catch2/catch.hpp>

#include <sundials/sundials_config.h>

#include <random>
#include <string>
#include <vector>

#include "nvector_test_support.hpp"

using namespace nvector_test;  // NOLINT(google-build-using-namespace): test helpers

TEST_CASE("fast vector fused and vector-array operations match NVECTOR_SERIAL",
          "[nvector_fast]") {
  Ctx c;
  const sunindextype n = GENERATE(as<sunindextype>{}, 1, 7, 1000);
  std::mt19937_64 rng(777 + static_cast<unsigned>(n));
  World w(c.ctx, n, 14);
  auto fresh = [&] { w.randomise(rng); };

  SECTION("LinearCombination") {
    struct Case {
      std::string name;
      std::vector<int> x;
      int z;
      std::vector<double> c;
    };
    const std::vector<Case> cases = {
        {"nvec=1", {0}, 8, {2.5}},
        {"nvec=1 c=1", {0}, 8, {1.0}},
        {"nvec=1 in place", {0}, 0, {-3.0}},
        {"nvec=2", {0, 1}, 8, {2.5, 0.7}},
        {"nvec=2 (1,-1)", {0, 1}, 8, {1.0, -1.0}},
        {"nvec=2 in place", {0, 1}, 0, {1.0, 0.5}},
        {"nvec=2 z==X1", {0, 1}, 1, {0.3, 1.0}},
        {"nvec=3", {0, 1, 2}, 8, {0.5, -1.5, 2.0}},
        {"nvec=6", {0, 1, 2, 3, 4, 5}, 8, {0.1, 0.2, -0.3, 0.4, 0.5, -0.6}},
        {"nvec=7", {0, 1, 2, 3, 4, 5, 6}, 8, {0.1, 0.2, -0.3, 0.4, 0.5, -0.6, 0.7}},
        {"nvec=11", {0, 1, 2, 3, 4, 5, 6, 7, 9, 10, 11}, 8,
         {1.1, 0.2, -0.3, 0.4, 0.5, -0.6, 0.7, 0.8, -0.9, 1.0, 1.1}},
        {"nvec=6 z==X0 c0=1", {0, 1, 2, 3, 4, 5}, 0, {1.0, 0.2, -0.3, 0.4, 0.5, -0.6}},
        {"nvec=6 z==X0 c0=2", {0, 1, 2, 3, 4, 5}, 0, {2.0, 0.2, -0.3, 0.4, 0.5, -0.6}},
        {"nvec=3 z==X2", {0, 1, 2}, 2, {0.5, -1.5, 2.0}},
        {"nvec=6 z==X0==X3", {0, 1, 2, 0, 4, 5}, 0, {1.0, 0.2, -0.3, 0.4, 0.5, -0.6}},
        {"nvec=6 z==X0==X3 c0!=1", {0, 1, 2, 0, 4, 5}, 0, {0.5, 0.2, -0.3, 0.4, 0.5, -0.6}},
        {"nvec=6 z==X5", {0, 1, 2, 3, 4, 5}, 5, {0.5, 0.2, -0.3, 0.4, 0.5, -0.6}},
        {"nvec=5 repeated X", {1, 1, 2, 2, 1}, 8, {0.5, 0.2, -0.3, 0.4, 0.5}},
    };
    for (const auto& cs : cases) {
      fresh();
      check_op(w, "LinearCombination " + cs.name, [&](const Getter& g) {
        std::vector<N_Vector> X;
        for (int i : cs.x) X.push_back(g(i));
        std::vector<double> cc = cs.c;
        const int rc = N_VLinearCombination(static_cast<int>(X.size()), cc.data(), X.data(), g(cs.z));
        return std::vector<Scalar>{{static_cast<double>(rc)}};
      });
    }
  }

  SECTION("LinearCombination with z's array shared by another vector") {
    // A second vector handle sharing z's array (as after N_VSetArrayPointer):
    // NVECTOR_SERIAL only compares handles, we compare arrays; the results
    // must still agree.
    for (int pos : {0, 1}) {
      fresh();
      check_op(w, "LinearCombination shared array at " + std::to_string(pos), [&](const Getter& g) {
        N_Vector z = g(8);
        VecPtr alias(N_VCloneEmpty(z));
        N_VSetArrayPointer(N_VGetArrayPointer(z), alias.get());
        std::vector<N_Vector> X = {g(0), g(1), g(2), g(3)};
        X[static_cast<size_t>(pos)] = alias.get();
        double cc[4] = {pos == 0 ? 1.0 : 0.5, 0.25, -2.0, 0.125};
        const int rc = N_VLinearCombination(4, cc, X.data(), z);
        return std::vector<Scalar>{{static_cast<double>(rc)}};
      });
    }
  }

  SECTION("ScaleAddMulti") {
    for (int nvec : {1, 3}) {
      double a[3] = {0.5, 1.0, -2.0};
      fresh();
      check_op(w, "ScaleAddMulti Z distinct", [&](const Getter& g) {
        auto Y = vecs(g, {1, 2, 3});
        auto Z = vecs(g, {4, 5, 6});
        return std::vector<Scalar>{{static_cast<double>(N_VScaleAddMulti(nvec, a, g(0), Y.data(), Z.data()))}};
      });
      fresh();
      check_op(w, "ScaleAddMulti Y==Z", [&](const Getter& g) {
        auto Y = vecs(g, {1, 2, 3});
        return std::vector<Scalar>{{static_cast<double>(N_VScaleAddMulti(nvec, a, g(0), Y.data(), Y.data()))}};
      });
      fresh();
      check_op(w, "ScaleAddMulti Z[i]==Y[i] (separate arrays), x==Y[1]", [&](const Getter& g) {
        auto Y = vecs(g, {1, 0, 3});
        auto Z = vecs(g, {1, 0, 3});
        return std::vector<Scalar>{{static_cast<double>(N_VScaleAddMulti(nvec, a, g(0), Y.data(), Z.data()))}};
      });
    }
  }

  SECTION("DotProdMulti") {
    for (int nvec : {1, 3}) {
      fresh();
      check_op(w, "DotProdMulti", [&](const Getter& g) {
        auto Y = vecs(g, {1, 0, 2});
        double d[3] = {0, 0, 0};
        const int rc = N_VDotProdMulti(nvec, g(0), Y.data(), d);
        std::vector<Scalar> out{{static_cast<double>(rc)}};
        for (int i = 0; i < nvec; ++i) out.push_back({d[i], abs_dot(w.serial(0), w.serial(i == 0 ? 1 : i == 1 ? 0 : 2))});
        return out;
      });
    }
  }

  SECTION("LinearSumVectorArray") {
    for (int nvec : {1, 3}) {
      for (const auto& [a, b] : kLinSumCoeffs) {
        for (int mode = 0; mode < 3; ++mode) {  // Z distinct, Z == X, Z == Y
          fresh();
          check_op(w, "LinearSumVectorArray a=" + std::to_string(a) + " b=" + std::to_string(b) +
                          " mode=" + std::to_string(mode),
                   [&, a = a, b = b](const Getter& g) {
                     auto X = vecs(g, {0, 1, 2});
                     auto Y = vecs(g, {3, 4, 5});
                     auto Z = vecs(g, {6, 7, 8});
                     N_Vector* Zp = mode == 0 ? Z.data() : mode == 1 ? X.data() : Y.data();
                     const int rc = N_VLinearSumVectorArray(nvec, a, X.data(), b, Y.data(), Zp);
                     return std::vector<Scalar>{{static_cast<double>(rc)}};
                   });
        }
      }
    }
  }

  SECTION("ScaleVectorArray, ConstVectorArray") {
    for (int nvec : {1, 3}) {
      for (const auto& coeffs : std::vector<std::array<double, 3>>{{2.5, -0.5, 3.0}, {1.0, -1.0, 1.0}, {-1.0, 0.0, 1.0}}) {
        for (bool in_place : {false, true}) {
          fresh();
          check_op(w, "ScaleVectorArray", [&](const Getter& g) {
            auto X = vecs(g, {0, 1, 2});
            auto Z = vecs(g, {3, 4, 5});
            std::array<double, 3> cc = coeffs;
            const int rc = N_VScaleVectorArray(nvec, cc.data(), X.data(), in_place ? X.data() : Z.data());
            return std::vector<Scalar>{{static_cast<double>(rc)}};
          });
        }
      }
      fresh();
      check_op(w, "ConstVectorArray", [&](const Getter& g) {
        auto Z = vecs(g, {3, 4, 5});
        return std::vector<Scalar>{{static_cast<double>(N_VConstVectorArray(nvec, -4.5, Z.data()))}};
      });
    }
  }

  SECTION("WrmsNormVectorArray, WrmsNormMaskVectorArray") {
    for (int nvec : {1, 3}) {
      fresh();
      for (sunindextype j = 0; j < n; j += 2) w.set(9, j, (j % 4 == 0) ? 0.0 : -1.0);
      check_op(w, "WrmsNorm(Mask)VectorArray", [&](const Getter& g) {
        auto X = vecs(g, {0, 1, 2});
        auto W = vecs(g, {3, 4, 3});
        double nrm[3] = {0, 0, 0}, nrmm[3] = {0, 0, 0};
        const int rc1 = N_VWrmsNormVectorArray(nvec, X.data(), W.data(), nrm);
        const int rc2 = N_VWrmsNormMaskVectorArray(nvec, X.data(), W.data(), g(9), nrmm);
        std::vector<Scalar> out{{static_cast<double>(rc1)}, {static_cast<double>(rc2)}};
        for (int i = 0; i < nvec; ++i) {
          out.push_back({nrm[i]});
          out.push_back({nrmm[i]});
        }
        return out;
      });
    }
  }

  SECTION("ScaleAddMultiVectorArray") {
    for (int nvec : {1, 2}) {
      for (int nsum : {1, 3}) {
        for (bool in_place : {false, true}) {
          fresh();
          check_op(w, "ScaleAddMultiVectorArray nvec=" + std::to_string(nvec) + " nsum=" +
                          std::to_string(nsum) + (in_place ? " Y==Z" : ""),
                   [&](const Getter& g) {
                     auto X = vecs(g, {0, 1});
                     std::vector<std::vector<N_Vector>> Yv = {vecs(g, {2, 3}), vecs(g, {4, 5}), vecs(g, {6, 7})};
                     std::vector<std::vector<N_Vector>> Zv = {vecs(g, {8, 9}), vecs(g, {10, 11}), vecs(g, {2, 3})};
                     std::vector<N_Vector*> Y, Z;
                     for (auto& v : Yv) Y.push_back(v.data());
                     for (auto& v : Zv) Z.push_back(v.data());
                     double a[3] = {0.5, -1.0, 2.0};
                     const int rc = N_VScaleAddMultiVectorArray(nvec, nsum, a, X.data(), Y.data(),
                                                                in_place ? Y.data() : Z.data());
                     return std::vector<Scalar>{{static_cast<double>(rc)}};
                   });
        }
      }
    }
  }

  SECTION("LinearCombinationVectorArray") {
    for (int nvec : {1, 2}) {
      for (int nsum : {1, 2, 3, 6}) {
        // Z distinct; Z == X[0] with c0 = 1; Z == X[0] with c0 = 0.5; Z a
        // different array holding the vectors of X[5] (a later term aliases z)
        for (int mode = 0; mode < 4; ++mode) {
          fresh();
          check_op(w, "LinearCombinationVectorArray nvec=" + std::to_string(nvec) + " nsum=" +
                          std::to_string(nsum) + " mode=" + std::to_string(mode),
                   [&](const Getter& g) {
                     std::vector<std::vector<N_Vector>> Xv;
                     for (int i = 0; i < 6; ++i) Xv.push_back(vecs(g, {2 * i % 12, (2 * i + 1) % 12}));
                     std::vector<N_Vector> Zv = mode == 3 ? vecs(g, {10, 11}) : vecs(g, {12, 13});
                     std::vector<N_Vector*> X;
                     for (auto& v : Xv) X.push_back(v.data());
                     double cc[6] = {mode == 1 ? 1.0 : 0.5, -0.25, 2.0, 0.75, -1.5, 0.125};
                     N_Vector* Z = (mode == 0 || mode == 3) ? Zv.data() : X[0];
                     const int rc = N_VLinearCombinationVectorArray(nvec, nsum, cc, X.data(), Z);
                     return std::vector<Scalar>{{static_cast<double>(rc)}};
                   });
        }
      }
    }
  }
}
