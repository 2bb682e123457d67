#include "explore/server.h"

#include <arpa/inet.h>
#include <netdb.h>
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
#include <map>
#include <mutex>
#include <new>
#include <thread>
#include <utility>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "explore/web_files.h"
#include "gonio/error.h"

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

std::string error_json(const std::string& message) { return nlohmann::json({{"error", message}}).dump(); }

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

}  // namespace

std::string host_name_of(const std::string& host_header) {
  if (!host_header.empty() && host_header[0] == '[') {
    const size_t close = host_header.find(']');
    return close == std::string::npos ? host_header : host_header.substr(0, close + 1);
  }
  return host_header.substr(0, host_header.find(':'));
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
  httplib::Server http;
  int bound_port = -1;
  // The stale flag of the latest request of each page and view (headers X-Gonio-Session
  // and X-Gonio-View): a newer request sets its predecessor's.
  std::mutex stale_mutex;
  std::map<std::string, std::shared_ptr<std::atomic<bool>>> latest;

  std::shared_ptr<std::atomic<bool>> supersede(const httplib::Request& req) {
    const std::string session = req.get_header_value("X-Gonio-Session");
    const std::string view = req.get_header_value("X-Gonio-View");
    if (session.empty() || view.empty() || session.size() > 64 || view.size() > 64) return nullptr;
    auto flag = std::make_shared<std::atomic<bool>>(false);
    const std::lock_guard<std::mutex> lock(stale_mutex);
    if (latest.size() > 10000) latest.clear();  // forgotten pages; the worst is a stale answer
    auto& slot = latest[session + "\n" + req.path + "\n" + view];
    if (slot) slot->store(true);
    slot = flag;
    return flag;
  }

  std::atomic<bool> stopping{false};
  std::atomic<bool> in_run{false};
  std::atomic<bool> done{false};

  // SPEC §3: refused (403) unless the Host header names this server, and an Origin, when
  // there is one, too: a page of another site (or one reached by DNS rebinding) gets
  // nothing.
  bool allowed(const httplib::Request& req, std::string& why) const {
    if (!req.has_header("Host")) {
      why = "refused: the request has no Host header";
      return false;
    }
    const std::string host = req.get_header_value("Host");
    if (!is_own_name(host_name_of(host), options.host)) {
      why = "refused: Host \"" + host + "\" is not this server's (127.0.0.1, [::1], localhost or --host)";
      return false;
    }
    if (req.has_header("Origin")) {
      const std::string origin = req.get_header_value("Origin");
      const size_t scheme = origin.find("://");
      const bool ok = scheme != std::string::npos &&
                      (origin.compare(0, scheme, "http") == 0 || origin.compare(0, scheme, "https") == 0) &&
                      is_own_name(host_name_of(origin.substr(scheme + 3)), options.host);
      if (!ok) {
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
    try {
      res.set_content(compute(), kJsonType);
      res.status = 200;
      timed();
    } catch (const InputError& e) {
      res.status = 400;
      res.set_content(error_json(e.what()), kJsonType);
    } catch (const Superseded& e) {
      res.status = 409;
      res.set_content(error_json(e.what()), kJsonType);
    } catch (const std::bad_alloc&) {
      res.status = 400;
      res.set_content(error_json("out of memory: ask for fewer angles, pixels or samples"), kJsonType);
    } catch (const std::exception& e) {
      res.status = 500;
      res.set_content(error_json(std::string("internal error: ") + e.what()), kJsonType);
    }
  }

  void route() {
    http.set_payload_max_length(kMaxBodyBytes);
    // Headers and body leave in separate writes: without this, Nagle's algorithm holds the
    // body until the client's delayed ACK of the headers, 40 ms later on Linux.
    http.set_tcp_nodelay(true);
    http.set_keep_alive_max_count(1000);
    http.set_keep_alive_timeout(5);
    http.set_read_timeout(10);
    http.set_write_timeout(10);
    const int threads = std::max(2, options.threads);
    http.new_task_queue = [threads] { return new httplib::ThreadPool(size_t(threads)); };
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      std::string why;
      if (allowed(req, why)) return httplib::Server::HandlerResponse::Unhandled;
      api_headers(res);
      res.status = 403;
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
        ApiContext request_ctx = ctx;
        request_ctx.stale = supersede(req);
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
  if (!s.stopping) ok = s.http.listen_after_bind();
  s.done = true;
  return ok || s.stopping;
}

void Server::stop() {
  Impl& s = *impl_;
  s.stopping = true;
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
