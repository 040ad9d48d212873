// A std::vector whose resize leaves new elements unset (default-initialised:
// no value for arithmetic types). For buffers a parallel loop fills entirely:
// the pages are then first touched by the threads that write them, instead
// of by one thread's zero pass (the mesh readers' parsed coordinates and ids,
// the skinning weights: 10 ms of zeroing at 1.66M vertices).

#ifndef MSDEFORM_CORE_UNINITIALIZED_VECTOR_H_
#define MSDEFORM_CORE_UNINITIALIZED_VECTOR_H_

#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace msdeform {

// std::allocator, except that construction without arguments
// default-initialises instead of value-initialising.
template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <typename U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}  // NOLINT: conversion
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <typename T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

}  // namespace msdeform

#endif  // MSDEFORM_CORE_UNINITIALIZED_VECTOR_H_
