// Counts heap allocations in a test binary (operator new replaced in allocation_counter.cpp), so
// that a test can assert that some code allocates nothing.
#pragma once

namespace rigid::test {

// Allocations made by operator new (any form) since the program started.
long allocation_count();

}  // namespace rigid::test
