// What one AES-256-GCM message costs after the CPU did something else for a while: the floor under
// DDS Security's latency for sporadic messages (issue 10; docs/security.md,
// figures in bench/notes/security.md).
//
// Cyclone DDS 0.10's cryptography plugin (Debian's libddsc0debian) encrypts and decrypts each
// payload and protected submessage with a cipher context made for that message: a new
// EVP_CIPHER_CTX, EVP_EncryptInit_ex with EVP_aes_256_gcm() (an implicit algorithm fetch in
// OpenSSL 3), the data, the tag, and the context freed. This benchmark does the same with the same
// library, after an idle gap, and splits the time into the set-up (context, fetch, key and IV) and
// the data. For comparison it also runs a context made once and re-keyed per message (what a plugin
// that kept its contexts would pay). Between messages the thread sleeps `idle` microseconds:
// the code and data the cipher needs leave the caches (and on a VM, the core) meanwhile.
//
//   cipher_cold_bench [--bytes N,...] [--idle-us US,...] [--repeats N]
//
// One line per case: RESULT cipher_us bytes B idle_us I context per_message|kept setup p50 S
// total p50 T p90 U. It asserts nothing (a benchmark, never run by ctest).
#include <openssl/evp.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace {

struct CtxFree {
  void operator()(EVP_CIPHER_CTX* c) const { EVP_CIPHER_CTX_free(c); }
};
struct CipherFree {
  void operator()(EVP_CIPHER* c) const { EVP_CIPHER_free(c); }
};
using Ctx = std::unique_ptr<EVP_CIPHER_CTX, CtxFree>;
using Cipher = std::unique_ptr<EVP_CIPHER, CipherFree>;

double now_us() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_nsec) * 1e-3;
}

void sleep_us(long us) {
  if (us <= 0) return;
  timespec t{us / 1000000, (us % 1000000) * 1000};
  while (clock_nanosleep(CLOCK_MONOTONIC, 0, &t, &t) != 0) {
  }
}

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr, "cipher_cold_bench: %s\n", what.c_str());
  std::fprintf(stderr,
               "usage: cipher_cold_bench [--bytes N,...] [--idle-us US,...] [--repeats N]\n");
  std::exit(2);
}

std::vector<long> parse_list(std::string_view option, std::string_view text, long lo, long hi) {
  std::vector<long> out;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    long v = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (ec != std::errc{} || end != item.data() + item.size() || v < lo || v > hi) {
      usage_error(std::string(option) + ": '" + std::string(item) + "' is not an integer in [" +
                  std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    out.push_back(v);
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
  }
  if (out.empty()) usage_error(std::string(option) + ": empty list");
  return out;
}

struct Times {
  std::vector<double> setup, total;
};

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

bool check(int ok, const char* what) {
  if (ok != 1) std::fprintf(stderr, "cipher_cold_bench: %s failed\n", what);
  return ok == 1;
}

// One message encrypted as Cyclone 0.10's plugin does: a context made, used and freed.
bool per_message(const unsigned char* key, const unsigned char* iv,
                 const std::vector<unsigned char>& in, std::vector<unsigned char>& out,
                 double& setup_done) {
  const Ctx ctx(EVP_CIPHER_CTX_new());
  if (!ctx) return check(0, "EVP_CIPHER_CTX_new");
  if (!check(EVP_EncryptInit_ex(ctx.get(), EVP_aes_256_gcm(), nullptr, nullptr, nullptr),
             "EVP_EncryptInit_ex") ||
      !check(EVP_EncryptInit_ex(ctx.get(), nullptr, nullptr, key, iv), "EVP_EncryptInit_ex key")) {
    return false;
  }
  setup_done = now_us();
  int len = 0, tail = 0;
  unsigned char tag[16];
  return check(
             EVP_EncryptUpdate(ctx.get(), out.data(), &len, in.data(), static_cast<int>(in.size())),
             "EVP_EncryptUpdate") &&
         check(EVP_EncryptFinal_ex(ctx.get(), out.data() + len, &tail), "EVP_EncryptFinal_ex") &&
         check(EVP_CIPHER_CTX_ctrl(ctx.get(), EVP_CTRL_GCM_GET_TAG, sizeof tag, tag), "get tag");
}

// The same message through a context kept from one message to the next, re-keyed each time.
bool kept(EVP_CIPHER_CTX* ctx, const unsigned char* key, const unsigned char* iv,
          const std::vector<unsigned char>& in, std::vector<unsigned char>& out,
          double& setup_done) {
  if (!check(EVP_EncryptInit_ex(ctx, nullptr, nullptr, key, iv), "EVP_EncryptInit_ex key"))
    return false;
  setup_done = now_us();
  int len = 0, tail = 0;
  unsigned char tag[16];
  return check(EVP_EncryptUpdate(ctx, out.data(), &len, in.data(), static_cast<int>(in.size())),
               "EVP_EncryptUpdate") &&
         check(EVP_EncryptFinal_ex(ctx, out.data() + len, &tail), "EVP_EncryptFinal_ex") &&
         check(EVP_CIPHER_CTX_ctrl(ctx, EVP_CTRL_GCM_GET_TAG, sizeof tag, tag), "get tag");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> bytes{1024, 106496}, idle{0, 500, 1000, 2000, 4000, 10000};
  long repeats = 200;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--help" || a == "-h") {
      std::printf(
          "usage: cipher_cold_bench [--bytes N,...] [--idle-us US,...] [--repeats N]\n"
          "AES-256-GCM per message after an idle gap, as Cyclone DDS 0.10's crypto plugin\n"
          "does it (a context per message) and with a kept context; see the source's top.\n");
      return 0;
    }
    if (i + 1 >= argc) usage_error(std::string(a) + " needs a value");
    const std::string_view v = argv[++i];
    if (a == "--bytes") {
      bytes = parse_list(a, v, 16, 64L << 20);
    } else if (a == "--idle-us") {
      idle = parse_list(a, v, 0, 1000000);
    } else if (a == "--repeats") {
      repeats = parse_list(a, v, 10, 100000).front();
    } else {
      usage_error("unknown option '" + std::string(a) + "'");
    }
  }
  const Cipher cipher(EVP_CIPHER_fetch(nullptr, "AES-256-GCM", nullptr));
  const Ctx kept_ctx(EVP_CIPHER_CTX_new());
  if (!cipher || !kept_ctx ||
      !check(EVP_EncryptInit_ex(kept_ctx.get(), cipher.get(), nullptr, nullptr, nullptr),
             "EVP_EncryptInit_ex")) {
    return 1;
  }
  unsigned char key[32], iv[12];
  for (unsigned i = 0; i < sizeof key; ++i)
    key[i] = static_cast<unsigned char>(17 * i + 3);
  for (unsigned i = 0; i < sizeof iv; ++i)
    iv[i] = static_cast<unsigned char>(5 * i + 1);
  for (const long n : bytes) {
    std::vector<unsigned char> in(static_cast<std::size_t>(n)), out(in.size() + 16);
    for (std::size_t i = 0; i < in.size(); ++i)
      in[i] = static_cast<unsigned char>(i * 31);
    for (const long gap : idle) {
      // The two ways alternate message by message, so that both see the same machine.
      Times t[2];
      for (long r = 0; r < repeats; ++r) {
        for (int way = 0; way < 2; ++way) {
          sleep_us(gap);
          double setup_done = 0.0;
          const double start = now_us();
          const bool ok = way == 0 ? per_message(key, iv, in, out, setup_done)
                                   : kept(kept_ctx.get(), key, iv, in, out, setup_done);
          const double end = now_us();
          if (!ok) return 1;
          t[way].setup.push_back(setup_done - start);
          t[way].total.push_back(end - start);
        }
      }
      for (int way = 0; way < 2; ++way) {
        std::printf(
            "RESULT cipher_us bytes %ld idle_us %ld context %s setup p50 %.1f total p50 %.1f "
            "p90 %.1f\n",
            n, gap, way == 0 ? "per_message" : "kept", quantile(t[way].setup, 0.5),
            quantile(t[way].total, 0.5), quantile(t[way].total, 0.9));
      }
      std::fflush(stdout);
    }
  }
  return 0;
}
