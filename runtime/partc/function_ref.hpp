// partc/function_ref.hpp: FunctionRef<R(Args...)>, a non-owning reference to
// a callable, as C++26's std::function_ref and LLVM's function_ref: passing a
// lambda to a function compiled in the runtime library allocates nothing
// (std::function would, for a lambda capturing more than two pointers, on
// every call), and calling it is one indirect call.
//
// Surprise: it refers to the callable, so the callable must outlive it; take
// it as a parameter, never store it.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

namespace partc {

template <class Signature>
class FunctionRef;

template <class R, class... Args>
class FunctionRef<R(Args...)> {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, FunctionRef>>>
  FunctionRef(F&& f)  // NOLINT(google-explicit-constructor): stands in for the callable
      : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_([](void* object, Args... args) -> R {
          return (*static_cast<std::remove_reference_t<F>*>(object))(std::forward<Args>(args)...);
        }) {}

  R operator()(Args... args) const { return call_(object_, std::forward<Args>(args)...); }

 private:
  void* object_;
  R (*call_)(void*, Args...);
};

}  // namespace partc
