// rigid-view serves the page's files that its web directory's served_files.txt names (the build
// writes it from clients/view/CMakeLists.txt's one list), each at its path with the content type of
// its extension, index.html at "/", nothing else; and refuses to start, naming the list's line or
// the file, when the list or a file it names is missing or not one a page may have.
#include <gtest/gtest.h>
#include <unistd.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "server.hpp"

namespace rigid::view {
namespace {

namespace http = boost::beast::http;
namespace fs = std::filesystem;

// A web directory of its own under the test's temporary directory, removed at the end.
class WebDir {
 public:
  WebDir() : path_(fs::temp_directory_path() / ("rigid_view_served_" + std::to_string(getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_ / "three");
  }
  ~WebDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name, std::ios::binary) << text;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

ServerOptions options(const fs::path& web_dir) {
  ServerOptions o;
  o.port = 0;  // any free port
  o.web_dir = web_dir;
  return o;
}

struct Response {
  unsigned status = 0;
  std::string type;
  std::string body;
};

Response get(std::uint16_t port, const std::string& target) {
  boost::asio::io_context ioc;
  boost::beast::tcp_stream stream(ioc);
  stream.connect({boost::asio::ip::make_address("127.0.0.1"), port});
  http::request<http::empty_body> request(http::verb::get, target, 11);
  request.set(http::field::host, "127.0.0.1");
  http::write(stream, request);
  boost::beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  return {response.result_int(), std::string(response[http::field::content_type]), response.body()};
}

// The one-line error the server throws for this directory, or "" if it starts.
std::string refusal(const fs::path& web_dir) {
  try {
    ViewServer server(options(web_dir), nullptr, nullptr);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ViewServedFiles, ServesWhatTheListNamesAndNothingElse) {
  WebDir dir;
  dir.write("index.html", "<!doctype html>page");
  dir.write("app.js", "export const a = 1;");
  dir.write("style.css", "body {}");
  dir.write("three/three.module.js", "export {};");
  dir.write("empty.js", "");
  dir.write("unlisted.js", "secret");
  dir.write("served_files.txt", "index.html\napp.js\nstyle.css\nthree/three.module.js\nempty.js\n");
  ViewServer server(options(dir.path()), nullptr, nullptr);
  server.start();
  const std::uint16_t port = server.port();

  const Response page = get(port, "/");
  EXPECT_EQ(page.status, 200u);
  EXPECT_EQ(page.type, "text/html; charset=utf-8");
  EXPECT_EQ(page.body, "<!doctype html>page");
  const Response app = get(port, "/app.js?v=2");  // (a query is not part of the path)
  EXPECT_EQ(app.status, 200u);
  EXPECT_EQ(app.type, "text/javascript; charset=utf-8");
  EXPECT_EQ(app.body, "export const a = 1;");
  EXPECT_EQ(get(port, "/style.css").type, "text/css; charset=utf-8");
  const Response three = get(port, "/three/three.module.js");
  EXPECT_EQ(three.status, 200u);
  EXPECT_EQ(three.body, "export {};");
  const Response empty = get(port, "/empty.js");
  EXPECT_EQ(empty.status, 200u);
  EXPECT_EQ(empty.body, "");
  // In the directory but not in the list, the list itself, index.html by name: not served.
  for (const char* target : {"/unlisted.js", "/served_files.txt", "/index.html", "/three/"})
    EXPECT_EQ(get(port, target).status, 404u) << target;
  server.stop();
}

TEST(ViewServedFiles, RefusesToStartNamingWhatIsWrong) {
  WebDir dir;
  dir.write("index.html", "page");
  dir.write("app.js", "code");
  EXPECT_NE(refusal(dir.path()).find("served_files.txt is missing"), std::string::npos)
      << refusal(dir.path());

  dir.write("served_files.txt", "index.html\napp.js\nthree/three.module.js\n");
  std::string why = refusal(dir.path());
  EXPECT_NE(why.find("three/three.module.js (served_files.txt line 3) is missing"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("npm ci"), std::string::npos) << why;

  for (const char* bad : {"../app.js", "/etc/passwd", "three/../app.js", "./app.js", "a//b.js",
                          "image.png", "app.js\r", "app js.js", ".js", "three/"}) {
    dir.write("served_files.txt", std::string("index.html\n") + bad + "\n");
    why = refusal(dir.path());
    EXPECT_NE(why.find("served_files.txt line 2: '"), std::string::npos) << bad << ": " << why;
    EXPECT_NE(why.find("is not a relative path of an .html, .js or .css file"), std::string::npos)
        << bad << ": " << why;
  }

  dir.write("served_files.txt", "app.js\n");
  EXPECT_NE(refusal(dir.path()).find("does not name index.html"), std::string::npos);
  dir.write("served_files.txt", "index.html\napp.js\napp.js\n");
  EXPECT_NE(refusal(dir.path()).find("line 3: app.js is named twice"), std::string::npos);
  dir.write("served_files.txt", std::string(64 * 1024, 'a') + ".js\n");
  EXPECT_NE(refusal(dir.path()).find("too long"), std::string::npos);

  // Bounded memory: the files together at most 64 MiB (a sparse file: its size costs no disk).
  dir.write("big.js", "");
  fs::resize_file(dir.path() / "big.js", (std::uintmax_t{64} << 20) - 3);
  dir.write("served_files.txt", "index.html\nbig.js\n");  // 64 MiB - 3 + the 4 of index.html
  EXPECT_NE(refusal(dir.path()).find("more than 64 MiB of files, at big.js"), std::string::npos)
      << refusal(dir.path());

  dir.write("served_files.txt", "index.html\napp.js");  // (no newline at the end: still a line)
  EXPECT_EQ(refusal(dir.path()), "");
}

}  // namespace
}  // namespace rigid::view
