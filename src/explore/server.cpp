#include "explore/server.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <list>
#include <map>
#include <mutex>
#include <new>
#include <optional>
#include <string_view>
#include <thread>
#include <utility>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "explore/web_files.h"
#include "gonio/error.h"
#include "gonio/json_text.h"

namespace gonio::explore {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool is_ipv6_literal(const std::string& host) { return host.find(':') != std::string::npos; }

// The host as it appears in a URL and a Host header: an IPv6 literal in brackets.
std::string url_host(const std::string& host) { return is_ipv6_literal(host) ? "[" + host + "]" : host; }

// The JSON answers' type. The charset parameter (meaningless for JSON, harmless) also keeps
// httplib from compressing them: it Brotli-compresses an exactly "application/json" body at
// Brotli's highest quality whenever the browser accepts br, which took 100–400 ms per
// answer of a few kB on two cores (measured in Chromium: a lobe computed in 0.8 ms arrived
// 290 ms after it was asked), far more than the loopback transfer it saves.
constexpr const char* kJsonType = "application/json; charset=utf-8";

// A message may quote bytes the client sent (a path, a header): printable_utf8 makes it
// valid UTF-8, without which dump() throws and the answer became a 500.
std::string error_json(const std::string& message) {
  return nlohmann::json({{"error", printable_utf8(message)}}).dump();
}

// Requests larger than this are refused (413) before they are read whole: the largest
// legitimate body is an /api/eval of kMaxEvalPairs pairs.
constexpr size_t kMaxBodyBytes = size_t(16) << 20;

// Resolves --host to a bindable address; InputError when it is none of this machine's.
void check_bindable(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* res = nullptr;
  const std::string service = std::to_string(port);
  const int rc = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &res);
  if (rc != 0 || !res)
    throw InputError("--host " + host + ": not an address this machine can listen on (" + gai_strerror(rc) + ")");
  // Bind a probe socket, to name the reason when the port cannot be had.
  const int fd = ::socket(res->ai_family, res->ai_socktype, res->ai_protocol);
  int err = 0;
  if (fd >= 0) {
    const int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, res->ai_addr, res->ai_addrlen) != 0) err = errno;
    ::close(fd);
  }
  ::freeaddrinfo(res);
  if (err == EADDRINUSE)
    throw InputError("--port " + std::to_string(port) + ": " + url_host(host) + ":" + std::to_string(port) +
                     " is already in use (give another --port, or 0 for any free one)");
  if (err == EADDRNOTAVAIL)
    throw InputError("--host " + host + ": not an address of this machine");
  if (err != 0)
    throw InputError("--port " + std::to_string(port) + ": cannot listen on " + url_host(host) + ":" +
                     std::to_string(port) + " (" + std::strerror(err) + ")");
}

// httplib listens with a backlog of 5 (CPPHTTPLIB_LISTEN_BACKLOG, compiled into Debian's
// libcpp-httplib): 20 browser sessions connecting at once overflowed it, and some of
// their first requests failed. Linux takes a second listen() on a listening socket as a
// new backlog; the socket is found among this process's descriptors by its port.
void widen_backlog(int port) {
  for (int fd = 0; fd < 4096; ++fd) {
    int listening = 0;
    socklen_t len = sizeof listening;
    if (::getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &len) != 0 || !listening) continue;
    sockaddr_storage addr{};
    socklen_t alen = sizeof addr;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &alen) != 0) continue;
    const int p = addr.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&addr)->sin6_port)
                                              : ntohs(reinterpret_cast<sockaddr_in*>(&addr)->sin_port);
    if (p == port) ::listen(fd, SOMAXCONN);
  }
}

// ---- connections ---------------------------------------------------------------------

// The socket of the connection whose request this thread is serving (set around each
// request by ExplorerHttp): the watchdog looks at it to stop work whose client has gone.
thread_local int t_connection_fd = -1;

// Waits up to `ms` for `events` on `fd`; true when they (or a hang-up or error) came.
bool wait_for(int fd, short events, int ms) {
  pollfd p{fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, std::max(0, ms));
    if (r >= 0) return r > 0;
    if (errno != EINTR) return false;
  }
}

std::string numeric_address(const sockaddr_storage& a, int& port) {
  char buf[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET6) {
    const auto& a6 = reinterpret_cast<const sockaddr_in6&>(a);
    ::inet_ntop(AF_INET6, &a6.sin6_addr, buf, sizeof buf);
    port = ntohs(a6.sin6_port);
  } else if (a.ss_family == AF_INET) {
    const auto& a4 = reinterpret_cast<const sockaddr_in&>(a);
    ::inet_ntop(AF_INET, &a4.sin_addr, buf, sizeof buf);
    port = ntohs(a4.sin_port);
  }
  return buf;
}

// One connection's byte stream for httplib's request parser. httplib's own stream keeps
// the bytes it read past a request in a buffer that lives for that request only, so a
// second request pipelined behind the first was read, dropped, and never answered; this
// one keeps them for the next request of the connection. Reads also stop at a deadline
// for the whole request (head and body), so that a client sending a byte every few
// seconds cannot hold a thread for ever.
class ConnectionStream final : public httplib::Stream {
 public:
  ConnectionStream(int fd, int timeout_ms) : fd_(fd), timeout_ms_(timeout_ms) {}

  bool has_buffered() const { return off_ < buf_.size(); }
  void start_request() {
    deadline_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms_);
    head_.clear();
    head_done_ = false;
  }
  // The current request's head as sent (request line and header lines, at most 64 KiB):
  // httplib drops a header line with an empty value, which the Origin check must see.
  std::string_view head() const { return head_; }

  bool is_readable() const override { return has_buffered() || wait_for(fd_, POLLIN, read_ms()); }
  bool is_writable() const override { return wait_for(fd_, POLLOUT, timeout_ms_); }

  ssize_t read(char* ptr, size_t size) override {
    const ssize_t n = read_bytes(ptr, size);
    if (n > 0 && !head_done_) {
      head_.append(ptr, size_t(n));
      head_done_ = head_.size() > 65536 || head_.find("\r\n\r\n") != std::string::npos ||
                   head_.find("\n\n") != std::string::npos;
    }
    return n;
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!wait_for(fd_, POLLOUT, timeout_ms_)) return -1;
    ssize_t sent;
    do sent = ::send(fd_, ptr, size, MSG_NOSIGNAL);
    while (sent < 0 && errno == EINTR);
    return sent;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage a{};
    socklen_t len = sizeof a;
    port = 0;
    ip = ::getpeername(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0 ? numeric_address(a, port) : "";
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage a{};
    socklen_t len = sizeof a;
    port = 0;
    ip = ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0 ? numeric_address(a, port) : "";
  }
  socket_t socket() const override { return fd_; }

 private:
  ssize_t read_bytes(char* ptr, size_t size) {
    if (size == 0) return 0;
    if (has_buffered()) {
      const size_t n = std::min(size, buf_.size() - off_);
      std::memcpy(ptr, buf_.data() + off_, n);
      off_ += n;
      if (off_ == buf_.size()) buf_.clear(), off_ = 0;
      return ssize_t(n);
    }
    if (!wait_for(fd_, POLLIN, read_ms())) return -1;
    char chunk[4096];
    ssize_t got;
    do got = ::recv(fd_, chunk, sizeof chunk, 0);
    while (got < 0 && errno == EINTR);
    if (got <= 0) return got;
    const size_t n = std::min(size, size_t(got));
    std::memcpy(ptr, chunk, n);
    buf_.assign(chunk + n, size_t(got) - n);
    off_ = 0;
    return ssize_t(n);
  }
  int read_ms() const {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - std::chrono::steady_clock::now());
    return int(std::clamp<long long>(left.count(), 0, timeout_ms_));
  }
  int fd_;
  int timeout_ms_;
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::now();
  std::string buf_;
  size_t off_ = 0;
  std::string head_;
  bool head_done_ = false;
};

// The stream of the request this thread is serving (its raw head, for the Origin check).
thread_local const ConnectionStream* t_stream = nullptr;

// Whether the raw request head has a header line `name` (case-insensitive) whose value
// is empty or blank.
bool has_blank_header(std::string_view head, std::string_view name) {
  size_t at = head.find('\n');
  while (at != std::string_view::npos && at + 1 < head.size()) {
    const size_t start = at + 1;
    const size_t end = std::min(head.find('\n', start), head.size());
    std::string_view line = head.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const size_t colon = line.find(':');
    if (colon == name.size() && lower(std::string(line.substr(0, colon))) == name &&
        line.find_first_not_of(" \t", colon + 1) == std::string_view::npos)
      return true;
    at = end < head.size() ? end : std::string_view::npos;
  }
  return false;
}

// httplib's server with its connection loop replaced (process_and_close_socket, virtual):
// requests read through ConnectionStream, the connection's socket known to the handlers,
// and idle keep-alive connections let go once threads run short.
class ExplorerHttp final : public httplib::Server {
 public:
  int threads = 64;
  int timeout_ms = 10000;
  int keep_alive_ms = 5000;
  std::atomic<int> connections{0};  // held by a thread now
  std::atomic<bool> stopping{false};

 private:
  // Threads left free for new connections: idle connections close once fewer remain.
  int spare() const { return std::max(1, threads / 8); }
  bool pressed() const { return connections.load() > threads - spare(); }

  // Until the next request's first byte (true), or false when the connection should
  // close: the keep-alive time passed, the client left, the server stops, or threads run
  // short (an idle connection must not keep a new one waiting).
  // A new connection's first request gets `timeout_ms`, or half a second once threads run
  // short (a browser sends it at once; a speculative connection may never).
  bool await_request(int fd, bool first) const {
    const auto start = std::chrono::steady_clock::now();
    const auto end = start + std::chrono::milliseconds(first ? timeout_ms : keep_alive_ms);
    for (;;) {
      if (stopping || svr_sock_ == INVALID_SOCKET) return false;
      if (pressed() && (!first || std::chrono::steady_clock::now() - start > std::chrono::milliseconds(500))) return false;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      if (wait_for(fd, POLLIN, int(std::min<long long>(left.count(), 50)))) return true;
    }
  }

  bool process_and_close_socket(socket_t sock) override {
    ++connections;
    ConnectionStream strm(sock, timeout_ms);
    bool ok = true;
    for (int count = 1000; count > 0 && !stopping && svr_sock_ != INVALID_SOCKET; --count) {
      // A request already buffered (pipelined) is served without waiting.
      if (!strm.has_buffered() && !await_request(sock, count == 1000)) break;
      strm.start_request();
      bool closed = false;
      const bool last = count == 1 || stopping || pressed();
      t_connection_fd = sock;
      t_stream = &strm;
      ok = process_request(strm, last, closed, {});
      t_connection_fd = -1;
      t_stream = nullptr;
      if (!ok || closed || last) break;
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    --connections;
    return ok;
  }
};

// The client of a connection has gone: it closed (a read would return 0) or reset it.
// Bytes it sent ahead (a pipelined request) are only peeked at.
bool client_gone(int fd) {
  if (fd < 0) return false;
  char c;
  const ssize_t n = ::recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT);
  return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
}


}  // namespace

std::optional<std::string> authority_host(std::string_view authority) {
  // RFC 9110 §7.2: Host = uri-host [ ":" port ]; RFC 3986 §3.2.2–3.2.3: the host is an
  // IP-literal in brackets, an IPv4 address or a reg-name, the port digits. Nothing else
  // may follow the host: "[::1].evil.com", "localhost@evil.com" and "localhost/x" are not
  // authorities of this server, whatever they start with.
  std::string_view host, rest;
  if (!authority.empty() && authority[0] == '[') {
    const size_t close = authority.find(']');
    if (close == std::string_view::npos || close < 2) return std::nullopt;
    host = authority.substr(0, close + 1);
    rest = authority.substr(close + 1);
    for (const char c : host.substr(1, host.size() - 2))
      if (!std::isxdigit(static_cast<unsigned char>(c)) && c != ':' && c != '.') return std::nullopt;
  } else {
    const size_t colon = authority.find(':');
    host = authority.substr(0, colon);
    rest = colon == std::string_view::npos ? std::string_view() : authority.substr(colon);
    if (host.empty()) return std::nullopt;
    // A reg-name of letters, digits, '-', '.', '_' and '~' (the unreserved characters;
    // percent-encoding and sub-delimiters name no host of this machine).
    for (const char c : host)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.' && c != '_' && c != '~')
        return std::nullopt;
  }
  if (!rest.empty()) {
    if (rest[0] != ':' || rest.size() > 6) return std::nullopt;
    for (const char c : rest.substr(1))
      if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
  }
  return lower(std::string(host));
}

bool is_own_name(const std::string& name, const std::string& host) {
  const std::string n = lower(name);
  return n == "127.0.0.1" || n == "[::1]" || n == "localhost" || (!host.empty() && n == lower(url_host(host)));
}

// Runs `work` on a thread of its own at a lower priority (nice + 10; Linux gives each
// thread its own nice value, and threads it starts inherit it): the page's refinements
// (the sphere's later passes, the albedo's second estimate) then yield both cores to the
// requests that follow a slider, instead of sharing them.
void run_in_background(const std::function<void()>& work) {
  std::exception_ptr failure;
  std::thread t([&] {
    const auto tid = static_cast<id_t>(::syscall(SYS_gettid));
    errno = 0;
    const int nice_now = ::getpriority(PRIO_PROCESS, tid);
    if (errno == 0) (void)::setpriority(PRIO_PROCESS, tid, std::min(19, nice_now + 10));
    try {
      work();
    } catch (...) {
      failure = std::current_exception();
    }
  });
  t.join();
  if (failure) std::rethrow_exception(failure);
}

struct Server::Impl {
  ServerOptions options;
  ApiContext ctx;
  ExplorerHttp http;
  int bound_port = -1;
  // The stop signal of the latest request of each page and view (headers X-Gonio-Session
  // and X-Gonio-View): a newer request raises its predecessor's.
  std::mutex stale_mutex;
  std::map<std::string, std::shared_ptr<StopSignal>> latest;

  void supersede(const httplib::Request& req, const std::shared_ptr<StopSignal>& signal) {
    const std::string session = req.get_header_value("X-Gonio-Session");
    const std::string view = req.get_header_value("X-Gonio-View");
    if (session.empty() || view.empty() || session.size() > 64 || view.size() > 64) return;
    const std::lock_guard<std::mutex> lock(stale_mutex);
    if (latest.size() > 10000) latest.clear();  // forgotten pages; the worst is a stale answer
    auto& slot = latest[session + "\n" + req.path + "\n" + view];
    if (slot) slot->raise(StopReason::Superseded);
    slot = signal;
  }

  // The requests at work, for the watchdog: each one's signal, connection and deadline.
  struct Watched {
    std::shared_ptr<StopSignal> signal;
    int fd;
    std::chrono::steady_clock::time_point deadline;
  };
  std::mutex watch_mutex;
  std::list<Watched> watched;
  std::thread watchdog;
  std::atomic<bool> watchdog_quit{false};

  // Every 20 ms: a request past its time limit, whose client has gone, or at work when
  // the server stops, has its signal raised; the work stops at its next step. (The
  // entries leave the list before their connection closes, so `fd` is still theirs.)
  void watch() {
    while (!watchdog_quit) {
      {
        const auto now = std::chrono::steady_clock::now();
        const std::lock_guard<std::mutex> lock(watch_mutex);
        for (const Watched& w : watched) {
          if (stopping) w.signal->raise(StopReason::ShuttingDown);
          else if (now > w.deadline) w.signal->raise(StopReason::TimeLimit);
          else if (client_gone(w.fd)) w.signal->raise(StopReason::ClientGone);
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }

  // A request's work, watched while it runs.
  struct WatchScope {
    Impl& impl;
    std::list<Watched>::iterator at;
    WatchScope(Impl& i, std::shared_ptr<StopSignal> signal) : impl(i) {
      const auto limit = std::chrono::duration<double>(impl.options.request_seconds);
      const std::lock_guard<std::mutex> lock(impl.watch_mutex);
      at = impl.watched.insert(impl.watched.end(),
                               {std::move(signal), t_connection_fd,
                                std::chrono::steady_clock::now() +
                                    std::chrono::duration_cast<std::chrono::steady_clock::duration>(limit)});
    }
    ~WatchScope() {
      const std::lock_guard<std::mutex> lock(impl.watch_mutex);
      impl.watched.erase(at);
    }
    WatchScope(const WatchScope&) = delete;
    WatchScope& operator=(const WatchScope&) = delete;
  };

  std::atomic<int> busy_posts{0};
  std::atomic<bool> stopping{false};
  std::atomic<bool> in_run{false};
  std::atomic<bool> done{false};

  // SPEC §3: refused unless the Host header names this server, and an Origin, when there
  // is one, too: a page of another site (or one reached by DNS rebinding) gets nothing.
  // A Host that is missing, given twice or malformed is a 400 (RFC 9110 §7.2, which
  // requires exactly one); one naming another machine, or any Origin not of this server,
  // a 403. `status` is set when the request is refused.
  bool allowed(const httplib::Request& req, std::string& why, int& status) const {
    const size_t hosts = req.get_header_value_count("Host");
    status = 400;
    if (hosts == 0) {
      why = "refused: the request has no Host header";
      return false;
    }
    if (hosts > 1) {
      why = "refused: the request has " + std::to_string(hosts) + " Host headers (one is allowed)";
      return false;
    }
    const std::string host = req.get_header_value("Host");
    const auto name = authority_host(host);
    if (!name) {
      why = "refused: Host \"" + host + "\" is not a host name with an optional port";
      return false;
    }
    status = 403;
    if (!is_own_name(*name, options.host)) {
      why = "refused: Host \"" + host + "\" is not this server's (127.0.0.1, [::1], localhost or --host)";
      return false;
    }
    const size_t origins = req.get_header_value_count("Origin");
    // httplib leaves out a header line whose value is empty: read from the raw head.
    if (t_stream && has_blank_header(t_stream->head(), "origin")) {
      why = "refused: an empty Origin header";
      return false;
    }
    if (origins > 1) {
      why = "refused: the request has " + std::to_string(origins) + " Origin headers";
      return false;
    }
    if (origins == 1) {
      // RFC 6454 §7: scheme "://" host [":" port], nothing after. An empty Origin, "null"
      // (a sandboxed or file: page) and a path are not this server's pages.
      const std::string origin = req.get_header_value("Origin");
      const size_t scheme = origin.find("://");
      const std::string s = scheme == std::string::npos ? "" : lower(origin.substr(0, scheme));
      const auto origin_name =
          scheme == std::string::npos ? std::nullopt : authority_host(std::string_view(origin).substr(scheme + 3));
      if ((s != "http" && s != "https") || !origin_name || !is_own_name(*origin_name, options.host)) {
        why = "refused: cross-origin request from \"" + origin + "\"";
        return false;
      }
    }
    return true;
  }

  static void api_headers(httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Content-Type-Options", "nosniff");
  }

  // A JSON endpoint: the api.h function's answer, or 400 with the CLI's one-line message.
  void answer(httplib::Response& res, const std::function<std::string()>& compute) const {
    api_headers(res);
    // The server's time for the answer, as Server-Timing (the browser's Resource Timing
    // reports it per request: the latency the page measures splits into this and the rest).
    const auto start = std::chrono::steady_clock::now();
    const auto timed = [&] {
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      char buf[48];
      std::snprintf(buf, sizeof buf, "app;dur=%.3f", ms);
      res.set_header("Server-Timing", buf);
    };
    const auto fail = [&](int status, const std::string& message) {
      res.status = status;
      res.set_content(error_json(message), kJsonType);
    };
    try {
      res.set_content(compute(), kJsonType);
      res.status = 200;
      timed();
    } catch (const InputError& e) {
      fail(400, e.what());
    } catch (const Stopped& e) {
      switch (e.reason) {
        case StopReason::Superseded: fail(409, e.what()); break;
        case StopReason::TimeLimit:
          fail(400, std::string(e.what()) + " (" + format_number(options.request_seconds) +
                        " s): ask for fewer samples, angles or pixels, or a smaller max_depth or samples of a "
                        "layered material");
          break;
        default: fail(503, e.what()); break;
      }
    } catch (const Busy& e) {
      res.set_header("Retry-After", "1");
      fail(429, e.what());
    } catch (const std::bad_alloc&) {
      fail(400, "out of memory: ask for fewer angles, pixels or samples");
    } catch (const std::exception& e) {
      fail(500, std::string("internal error: ") + e.what());
    }
  }

  void route() {
    http.set_payload_max_length(kMaxBodyBytes);
    // Headers and body leave in separate writes: without this, Nagle's algorithm holds the
    // body until the client's delayed ACK of the headers, 40 ms later on Linux.
    http.set_tcp_nodelay(true);
    const int threads = std::max(2, options.threads);
    http.threads = threads;
    http.keep_alive_ms = int(std::max(0.0, options.keep_alive_seconds) * 1000);
    http.timeout_ms = 10000;  // a request's head and body, and each write
    http.new_task_queue = [threads] { return new httplib::ThreadPool(size_t(threads)); };
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      std::string why;
      int status = 403;
      if (allowed(req, why, status)) return httplib::Server::HandlerResponse::Unhandled;
      api_headers(res);
      res.status = status;
      res.set_content(error_json(why), kJsonType);
      return httplib::Server::HandlerResponse::Handled;
    });
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
      res.status = 500;
      res.set_content(error_json("internal error"), kJsonType);
    });

    http.Get("/api/materials", [this](const httplib::Request&, httplib::Response& res) {
      answer(res, [] { return api_materials(); });
    });
    http.Get("/api/data", [this](const httplib::Request&, httplib::Response& res) {
      answer(res, [this] { return api_data(ctx); });
    });
    using Endpoint = std::string (*)(const std::string&, const ApiContext&);
    const std::pair<const char*, Endpoint> posts[] = {
        {"/api/validate", &api_validate}, {"/api/eval", &api_eval},     {"/api/lobe", &api_lobe},
        {"/api/slice", &api_slice},       {"/api/slice_point", &api_slice_point},
        {"/api/albedo", &api_albedo},     {"/api/fresnel", &api_fresnel}, {"/api/check", &api_check},
        {"/api/sphere", &api_sphere},     {"/api/lobe3d", &api_lobe3d}, {"/api/fit", &api_fit},
    };
    for (const auto& [path, fn] : posts) {
      http.Post(path, [this, fn = fn](const httplib::Request& req, httplib::Response& res) {
        // At most half the threads compute at once: the rest stay for the page, the
        // registry and light requests however many clients ask for heavy work.
        const int computing = ++busy_posts;
        struct Leave {
          std::atomic<int>& n;
          ~Leave() { --n; }
        } leave{busy_posts};
        if (computing > std::max(1, http.threads / 2)) {
          api_headers(res);
          res.status = 429;
          res.set_header("Retry-After", "1");
          res.set_content(error_json("busy: " + std::to_string(computing - 1) +
                                     " requests are being computed; try again when they are done"),
                          kJsonType);
          return;
        }
        ApiContext request_ctx = ctx;
        auto signal = std::make_shared<StopSignal>();
        supersede(req, signal);
        request_ctx.stop = signal;
        const WatchScope watching(*this, signal);
        // X-Gonio-Priority: background marks a refinement (docs/explore.md).
        if (req.get_header_value("X-Gonio-Priority") == "background") {
          answer(res, [&] {
            std::string out;
            run_in_background([&] { out = fn(req.body, request_ctx); });
            return out;
          });
        } else {
          answer(res, [&] { return fn(req.body, request_ctx); });
        }
      });
    }
    // The page: the embedded files, nothing from the disk.
    http.Get(R"(/(.*))", [](const httplib::Request& req, httplib::Response& res) {
      std::string name = req.matches[1];
      if (name.empty()) name = "index.html";
      for (const WebFile& f : web_files()) {
        if (f.name != name) continue;
        res.set_content(std::string(f.data), std::string(content_type(name)));
        res.set_header("Cache-Control", "no-cache");
        res.set_header("X-Content-Type-Options", "nosniff");
        // The page loads its own scripts and styles and talks to this server only.
        res.set_header("Content-Security-Policy",
                       "default-src 'self'; img-src 'self' data: blob:; connect-src 'self'; "
                       "frame-ancestors 'none'; base-uri 'none'; form-action 'none'");
        return;
      }
      res.status = 404;
      res.set_content(error_json("no such page: /" + name), kJsonType);
    });
  }
};

Server::Server(ServerOptions options) : impl_(std::make_unique<Impl>()) { impl_->options = std::move(options); }

Server::~Server() { stop(); }

void Server::bind() {
  Impl& s = *impl_;
  if (!s.options.data_dir.empty()) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto st = fs::status(s.options.data_dir, ec);
    if (st.type() == fs::file_type::not_found) throw InputError("--data " + s.options.data_dir + ": no such directory");
    if (st.type() != fs::file_type::directory) throw InputError("--data " + s.options.data_dir + ": not a directory");
    const fs::path canonical = fs::canonical(s.options.data_dir, ec);
    if (ec) throw InputError("--data " + s.options.data_dir + ": " + ec.message());
    s.ctx.data_dir = canonical.string();
  }
  if (!(s.options.port >= 0 && s.options.port <= 65535))
    throw InputError("--port must be 0 to 65535, got " + std::to_string(s.options.port));
  if (s.options.host.empty()) throw InputError("--host: empty");
  check_bindable(s.options.host, s.options.port);
  s.route();
  if (is_ipv6_literal(s.options.host)) s.http.set_address_family(AF_INET6);
  if (s.options.port == 0) {
    s.bound_port = s.http.bind_to_any_port(s.options.host);
    if (s.bound_port < 0) throw InputError("--host " + s.options.host + ": cannot listen on any port");
  } else {
    if (!s.http.bind_to_port(s.options.host, s.options.port))
      throw InputError("--port " + std::to_string(s.options.port) + ": cannot listen on " + url_host(s.options.host) +
                       ":" + std::to_string(s.options.port));
    s.bound_port = s.options.port;
  }
  widen_backlog(s.bound_port);
}

std::string Server::url() const {
  return "http://" + url_host(impl_->options.host) + ":" + std::to_string(impl_->bound_port) + "/";
}

int Server::port() const { return impl_->bound_port; }

bool Server::run() {
  Impl& s = *impl_;
  bool ok = true;
  s.in_run = true;
  s.watchdog_quit = false;
  s.watchdog = std::thread([&s] { s.watch(); });
  // The watchdog runs until listening has ended: httplib's stop() waits for the requests
  // at work, which stop at their next step once it has raised their signals.
  if (!s.stopping) ok = s.http.listen_after_bind();
  s.watchdog_quit = true;
  s.watchdog.join();
  s.done = true;
  return ok || s.stopping;
}

void Server::stop() {
  Impl& s = *impl_;
  s.stopping = true;
  s.http.stopping = true;  // idle connections close, busy ones after their answer
  // httplib's stop() acts only once listening has begun: repeat until run() has returned
  // (a signal may come between the start of run() and that of listening). A run() that
  // starts after this sees `stopping` and does not listen.
  while (s.in_run && !s.done) {
    s.http.stop();
    if (s.done) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace gonio::explore
