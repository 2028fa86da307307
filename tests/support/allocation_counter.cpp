// The global operator new / delete of a test binary, counting allocations. Every replaceable
// form is replaced: an allocation through a form left out (an over-aligned type's new, an array
// new, a nothrow new) would escape the count, and a sanitizer runtime defines each form itself,
// so that one left out would also pair its allocation with the free() below (ASan:
// alloc-dealloc-mismatch). In a translation unit of their own, so that the compiler cannot pair
// an inlined new with this delete's free() and raise a false -Wmismatched-new-delete. The
// counters are necessarily global: they are what replacing operator new means.
#include "allocation_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<long> g_allocations{0};
std::atomic<long> g_counted{0};
thread_local bool t_counting = false;

void count() {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (t_counting) g_counted.fetch_add(1, std::memory_order_relaxed);
}

void* allocate(std::size_t n) noexcept {
  count();
  return std::malloc(n == 0 ? 1 : n);
}

// aligned_alloc wants a size that is a non-zero multiple of the alignment.
void* allocate(std::size_t n, std::align_val_t a) noexcept {
  count();
  const std::size_t al = static_cast<std::size_t>(a);
  return std::aligned_alloc(al, n == 0 ? al : (n + al - 1) / al * al);
}

void* or_throw(void* p) {
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

namespace rigid::test {
long allocation_count() {
  return g_allocations.load(std::memory_order_relaxed);
}
long counted_allocations() {
  return g_counted.load(std::memory_order_relaxed);
}
void reset_counted_allocations() {
  g_counted.store(0, std::memory_order_relaxed);
}
CountingThread::CountingThread() {
  t_counting = true;
}
CountingThread::~CountingThread() {
  t_counting = false;
}
}  // namespace rigid::test

void* operator new(std::size_t n) {
  return or_throw(allocate(n));
}
void* operator new[](std::size_t n) {
  return or_throw(allocate(n));
}
void* operator new(std::size_t n, std::align_val_t a) {
  return or_throw(allocate(n, a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return or_throw(allocate(n, a));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return allocate(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return allocate(n);
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate(n, a);
}

void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
