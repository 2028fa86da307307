// util/thread_name.hpp: the name given to a thread is what /proc shows as soon as the call
// returns, cut to Linux's 15 bytes rather than refused; and the physics pool's workers are named by
// their index when the pool is made.
#include "util/thread_name.hpp"

#include <gtest/gtest.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <set>
#include <string>
#include <thread>

#include "physics/pool.hpp"

namespace rigid::util {
namespace {

std::string comm_of(const std::filesystem::path& task) {
  std::ifstream in(task / "comm");
  std::string name;
  std::getline(in, name);
  return name;
}

std::multiset<std::string> names_of_this_process() {
  std::multiset<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator("/proc/self/task"))
    names.insert(comm_of(e.path()));
  return names;
}

// A thread that waits until told to end, and says its id first.
struct Sleeper {
  std::promise<long> tid;
  std::promise<void> go;
  std::thread t{[this] {
    tid.set_value(static_cast<long>(syscall(SYS_gettid)));
    go.get_future().wait();
  }};
  ~Sleeper() {
    go.set_value();
    t.join();
  }
};

TEST(ThreadName, IsWhatProcShowsOnReturnAndALongOneIsCutToFifteenBytes) {
  Sleeper s;
  const std::filesystem::path task = "/proc/self/task/" + std::to_string(s.tid.get_future().get());
  name_thread(s.t, "rigid-test");
  EXPECT_EQ(comm_of(task), "rigid-test");
  name_thread(s.t, "rigid-a-name-longer-than-fifteen");
  EXPECT_EQ(comm_of(task), "rigid-a-name-lo");
}

TEST(ThreadName, ThePoolsWorkersAreNamedByTheirIndex) {
  const std::multiset<std::string> before = names_of_this_process();
  {
    physics::detail::Pool pool(3);  // the caller and two workers
    const std::multiset<std::string> during = names_of_this_process();
    EXPECT_EQ(during.count("rigid-step-1"), before.count("rigid-step-1") + 1);
    EXPECT_EQ(during.count("rigid-step-2"), before.count("rigid-step-2") + 1);
    EXPECT_EQ(during.count("rigid-step-3"), before.count("rigid-step-3"));
  }
  EXPECT_EQ(names_of_this_process().count("rigid-step-1"), before.count("rigid-step-1"));
}

}  // namespace
}  // namespace rigid::util
