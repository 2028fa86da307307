// What zstd's level buys on a real recording: reads FILE (any rigid log) once into memory, then
// writes its records again with common::RecordWriter, uncompressed and at each zstd level given,
// into /dev/shm (memory, so the disk's speed is not measured), REPEATS times each in turn, and
// prints per level the file's size, the ratio to uncompressed, and the writer's CPU time per MB of
// records (the median of the repeats): the cost a recorder pays for that ratio.
//
//   recording_levels FILE [--levels 1,3,6,9] [--repeats 3]
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "common/record_file.hpp"

namespace {

using rigid::common::Compression;
using rigid::common::RecordReader;
using rigid::common::RecordWriter;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Run {
  double cpu_s = 0;
  std::uintmax_t bytes = 0;
};

Run write_all(const std::vector<rigid::msgs::LogRecord>& records, const std::string& out,
              Compression c) {
  const double start = cpu_seconds();
  {
    RecordWriter w(out, true, c);
    for (std::size_t i = 0; i < records.size(); ++i) {
      w.append(records[i]);
      if (i % 10 == 9) w.flush();  // as rigid-record: a flush every 100 ms, 10 states at 100 Hz
    }
    w.close();
  }
  Run r;
  r.cpu_s = cpu_seconds() - start;
  r.bytes = std::filesystem::file_size(out);
  std::filesystem::remove(out);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: recording_levels FILE [--levels 1,3,6,9] [--repeats 3]\n");
    return 2;
  }
  std::vector<int> levels{1, 3, 6, 9};
  int repeats = 3;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string name = argv[i];
    if (name == "--levels") {
      levels.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string item; std::getline(list, item, ',');)
        levels.push_back(std::stoi(item));
    } else if (name == "--repeats") {
      repeats = std::max(1, std::stoi(argv[i + 1]));
    } else {
      std::fprintf(stderr, "recording_levels: unknown option %s\n", name.c_str());
      return 2;
    }
  }
  try {
    std::vector<rigid::msgs::LogRecord> records;
    {
      RecordReader reader(argv[1]);
      rigid::msgs::LogRecord r;
      while (reader.next(r))
        records.push_back(r);
    }
    const std::string out = "/dev/shm/recording_levels_" + std::to_string(::getpid()) + ".rlog";
    std::vector<int> kinds{0};  // 0: uncompressed
    kinds.insert(kinds.end(), levels.begin(), levels.end());
    std::vector<std::vector<Run>> runs(kinds.size());
    for (int k = 0; k < repeats; ++k) {
      for (std::size_t i = 0; i < kinds.size(); ++i) {
        Compression c;
        c.zstd = kinds[i] > 0;
        c.level = std::max(1, kinds[i]);
        runs[i].push_back(write_all(records, out, c));
      }
    }
    const double plain_mb = static_cast<double>(runs[0].front().bytes) / 1e6;
    std::printf("%s: %zu records, %.1f MB uncompressed, %d repeats (median CPU)\n", argv[1],
                records.size(), plain_mb, repeats);
    std::printf("%-10s %12s %8s %14s %12s\n", "writer", "MB", "ratio", "CPU s", "CPU ms/MB");
    for (std::size_t i = 0; i < kinds.size(); ++i) {
      std::vector<double> cpu;
      for (const Run& r : runs[i])
        cpu.push_back(r.cpu_s);
      std::sort(cpu.begin(), cpu.end());
      const double median = cpu[cpu.size() / 2];
      const double mb = static_cast<double>(runs[i].front().bytes) / 1e6;
      const std::string name = kinds[i] == 0 ? "none" : "zstd " + std::to_string(kinds[i]);
      std::printf("%-10s %12.2f %8.2f %14.3f %12.2f\n", name.c_str(), mb, plain_mb / mb, median,
                  1e3 * median / plain_mb);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "recording_levels: %s\n", e.what());
    return 1;
  }
}
