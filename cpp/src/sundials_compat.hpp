// The few places where SUNDIALS 6.x and 7.x differ, kept in one header so a
// build against any SUNDIALS >= 6.4 compiles the rest of the code unchanged.
#pragma once

#include <cvodes/cvodes.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>

#include <stdexcept>
#include <string>

#if SUNDIALS_VERSION_MAJOR < 6 || (SUNDIALS_VERSION_MAJOR == 6 && SUNDIALS_VERSION_MINOR < 4)
#error "pydrill needs SUNDIALS >= 6.4"
#endif

namespace pydrill::detail {

// Return codes of a SUNLinearSolver (7.x folded them into SUNErrCode).
#if SUNDIALS_VERSION_MAJOR >= 7
inline constexpr int kLinSolSuccess = SUN_SUCCESS;
inline constexpr int kLinSolFailUnrecoverable = SUN_ERR_EXT_FAIL;
#else
inline constexpr int kLinSolSuccess = SUNLS_SUCCESS;
inline constexpr int kLinSolFailUnrecoverable = SUNLS_PACKAGE_FAIL_UNREC;
#endif
inline constexpr int kLinSolFailRecoverable = SUNLS_PACKAGE_FAIL_REC;

// Owns one SUNContext; each simulation has its own, so runs are thread-safe.
class Context {
 public:
  Context() {
#if SUNDIALS_VERSION_MAJOR >= 7
    const int flag = SUNContext_Create(SUN_COMM_NULL, &ctx_);
#else
    const int flag = SUNContext_Create(nullptr, &ctx_);
#endif
    if (flag != 0 || ctx_ == nullptr) throw std::runtime_error("SUNContext_Create failed");
  }
  ~Context() { SUNContext_Free(&ctx_); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  operator SUNContext() const { return ctx_; }

 private:
  SUNContext ctx_ = nullptr;
};

// Route the integrators' error and warning messages into `sink` instead of
// stderr, so they can travel with the exception that reports the failure.
#if SUNDIALS_VERSION_MAJOR >= 7
inline void capture_messages(SUNContext ctx, std::string* sink) {
  SUNContext_ClearErrHandlers(ctx);
  SUNContext_PushErrHandler(
      ctx,
      [](int, const char* func, const char*, const char* msg, SUNErrCode, void* data, SUNContext) {
        auto* s = static_cast<std::string*>(data);
        *s = std::string(func ? func : "SUNDIALS") + ": " + (msg ? msg : "");
      },
      sink);
}
inline void capture_cvode_messages(void*, SUNContext ctx, std::string* sink) {
  capture_messages(ctx, sink);
}
inline void capture_arkode_messages(void*, SUNContext ctx, std::string* sink) {
  capture_messages(ctx, sink);
}
#else
inline void store_message(int, const char* module, const char* function, char* msg, void* data) {
  auto* s = static_cast<std::string*>(data);
  *s = std::string(module ? module : "SUNDIALS") + "/" + (function ? function : "") + ": " +
       (msg ? msg : "");
}
inline void capture_cvode_messages(void* cvode_mem, SUNContext, std::string* sink) {
  CVodeSetErrHandlerFn(cvode_mem, store_message, sink);
}
// Defined where ARKODE's header is included (integrator_erk.cpp).
void capture_arkode_messages(void* arkode_mem, SUNContext, std::string* sink);
#endif

}  // namespace pydrill::detail
