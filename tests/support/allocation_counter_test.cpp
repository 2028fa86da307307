// The allocation counter (allocation_counter.hpp) counts every form of operator new, on any
// thread and on counting threads only: a form it missed would let a test of "allocates nothing"
// pass while the code allocated through that form. The functions are called explicitly (a call
// of operator new, unlike a new-expression, is never elided by the compiler).
#include "allocation_counter.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <thread>

namespace rigid::test {
namespace {

constexpr std::align_val_t kLine{64};  // beyond __STDCPP_DEFAULT_NEW_ALIGNMENT__: aligned forms

// Calls every replaceable form once, each allocation freed by its matching delete.
void every_form() {
  ::operator delete(::operator new(8));
  ::operator delete[](::operator new[](8));
  ::operator delete(::operator new(8, kLine), kLine);
  ::operator delete[](::operator new[](8, kLine), kLine);
  ::operator delete(::operator new(8, std::nothrow), std::nothrow);
  ::operator delete[](::operator new[](8, std::nothrow), std::nothrow);
  ::operator delete(::operator new(8, kLine, std::nothrow), kLine, std::nothrow);
  ::operator delete[](::operator new[](8, kLine, std::nothrow), kLine, std::nothrow);
}
constexpr long kForms = 8;

TEST(AllocationCounter, CountsEveryFormOnAnyThread) {
  const long before = allocation_count();
  every_form();
  EXPECT_EQ(allocation_count() - before, kForms);
}

TEST(AllocationCounter, AlignedFormsReturnAlignedMemory) {
  void* p = ::operator new(100, kLine);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % 64, 0u);
  ::operator delete(p, kLine);
  void* q = ::operator new[](0, kLine, std::nothrow);
  EXPECT_NE(q, nullptr);  // a zero-size request still gets its own pointer
  ::operator delete[](q, kLine);
}

TEST(AllocationCounter, CountsOnlyOnCountingThreads) {
  reset_counted_allocations();
  std::thread quiet(every_form);
  quiet.join();
  EXPECT_EQ(counted_allocations(), 0);
  std::thread counting([] {
    const CountingThread on;
    every_form();
  });
  counting.join();
  EXPECT_EQ(counted_allocations(), kForms);
  every_form();  // this thread does not count
  EXPECT_EQ(counted_allocations(), kForms);
}

}  // namespace
}  // namespace rigid::test
