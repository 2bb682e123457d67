#pragma once
// The explorer's HTTP server (`gonio explore`, SPEC §3): the page's embedded files and the
// JSON API of api.h over cpp-httplib, refusing requests whose Host or Origin names another
// machine (DNS rebinding, cross-origin pages). httplib stays out of this header, so that the
// CLI compiles without it.

#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace gonio::explore {

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;        // 0: any free port (the URL names the one chosen)
  std::string data_dir;   // --data, as given; empty: none
  int threads = 64;       // connections served at once (a browser keeps up to 6 open)
  // The longest a request's work runs (its time limit, docs/explore.md "Limits"); past
  // it the work stops at its next step and the answer is a 400.
  double request_seconds = 30;
  // How long an idle keep-alive connection is kept (seconds), when threads are free; once
  // most are busy, idle connections are closed at once.
  double keep_alive_seconds = 5;
};

class Server {
 public:
  explicit Server(ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Checks the options and binds the socket: throws InputError naming the option (no such
  // directory for --data, a host that is no address of this machine, a port in use).
  void bind();
  // http://HOST:PORT/ once bound (an IPv6 host in brackets).
  std::string url() const;
  int port() const;
  // Serves until stop(); returns false when listening failed.
  bool run();
  // From any thread, at any time (before run() too): run() returns soon after.
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Whether `name` (the host of a Host header or of an Origin, as authority_host gives it) is
// one of the server's own names: 127.0.0.1, [::1], localhost, or the --host value `host`.
bool is_own_name(const std::string& name, const std::string& host);
// The host of an authority (a Host header's value, an Origin after its "scheme://"),
// lower-case, an IPv6 literal with its brackets: "LocalHost:8080" -> "localhost",
// "[::1]:80" -> "[::1]". Nothing when the text is not host[:port] (RFC 9110 §7.2, RFC 3986
// §3.2.2): text after "]" or the port ("[::1].evil.com"), userinfo, a path, an empty host.
std::optional<std::string> authority_host(std::string_view authority);

}  // namespace gonio::explore
