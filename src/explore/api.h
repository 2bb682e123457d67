#pragma once
// The JSON API of `gonio explore` (issue 36, SPEC §3), without HTTP: each endpoint is a
// function from the request body (JSON text) to the response body (JSON text), computed by
// the core library and the renderer's slice — no model is evaluated anywhere else. A bad
// request throws gonio::InputError with the one-line message the CLI would print (the
// server answers it with HTTP 400 {"error": message}). docs/explore.md documents each one.

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace gonio::explore {

// Why a request's work stopped before its end (the server answers each differently:
// docs/explore.md, "Limits").
enum class StopReason : int {
  None = 0,
  Superseded,    // a newer request of the same page and view arrived: 409
  TimeLimit,     // past the server's time per request: 400
  ClientGone,    // the client closed the connection: nobody to answer
  ShuttingDown,  // the server is stopping (SIGINT): 503
};

// The flag the long endpoints poll between steps (the renderer between tiles, the
// validator between properties, the albedo between angles); set from another thread
// (the server's watchdog, a newer request), the first reason kept.
struct StopSignal {
  std::atomic<bool> stop{false};
  std::atomic<int> reason{0};
  void raise(StopReason r) noexcept {
    int none = 0;
    reason.compare_exchange_strong(none, int(r));
    stop.store(true);
  }
  StopReason why() const noexcept { return StopReason(reason.load()); }
};

// Thrown by an endpoint whose StopSignal was raised.
struct Stopped : std::runtime_error {
  StopReason reason;
  explicit Stopped(StopReason r);
};

// Thrown when a one-at-a-time endpoint (check, fit) has its queue full: the server
// answers 429 at once rather than hold a thread for minutes.
struct Busy : std::runtime_error {
  explicit Busy(const std::string& what);
};

// One at a time, at most `max_waiting` more waiting; a waiting request leaves when its
// StopSignal is raised (superseded, time limit, client gone, shutdown).
class OneAtATime {
 public:
  explicit OneAtATime(int max_waiting) : max_waiting_(max_waiting) {}
  void acquire(const struct ApiContext& ctx, const char* what);  // Busy, Stopped
  void release();

 private:
  std::mutex mutex_;
  std::condition_variable freed_;
  bool busy_ = false;
  int waiting_ = 0;
  int max_waiting_;
};

// What every request may refer to: the --data directory (canonical, absolute; empty when
// none was given). A material's file names ("file" of `measured`, a {"spectrum": "x.csv"})
// must name files inside it; anything else is refused, so that a page cannot make the
// server read the rest of the disk.
struct ApiContext {
  std::string data_dir;
  // Raised by the server (a newer request of the same page and view, the time limit, the
  // client gone, shutdown); the long endpoints poll it between steps and throw Stopped.
  std::shared_ptr<const StopSignal> stop;
  void check_stop() const {
    if (stop && stop->stop.load(std::memory_order_relaxed)) throw Stopped(stop->why());
  }
};

// The work a request may imply, in walk steps (evaluation_cost.h) times evaluations: a
// request above it is refused up front with a 400 naming its estimate. Analytic models
// stay far below; a layered material's max_depth × samples is what reaches it. A step
// took 3–12 ns on the machine of docs/benchmarks.md (a default layered material's
// validation, 4·10⁹ steps, 27 s; an albedo-1 medium walking to max_depth 10000, 3.4 ns),
// so the bound is a minute or two of a core at worst; the time limit stops it sooner.
inline constexpr double kMaxRequestWork = 1e10;

// GET /api/materials: the registry behind `gonio materials` — every type with its
// parameters (kind, default, range, choices, meaning), a valid example per type, the
// named metals and glasses, and the wavelength range of spectral mode.
std::string api_materials();
// GET /api/data: the regular files directly inside --data (names only).
std::string api_data(const ApiContext& ctx);

// POST endpoints. Every body is a JSON object; "bsdf" holds the material (an object, or
// its JSON text as a string: the parser then reports syntax errors as `gonio eval` does),
// and "wavelength" (nm, where the CLI has --wavelength) selects spectral mode.
std::string api_validate(const std::string& body, const ApiContext& ctx);     // /api/validate
std::string api_eval(const std::string& body, const ApiContext& ctx);         // /api/eval (SPEC §3)
std::string api_lobe(const std::string& body, const ApiContext& ctx);         // /api/lobe
std::string api_lobe3d(const std::string& body, const ApiContext& ctx);       // /api/lobe3d
std::string api_slice(const std::string& body, const ApiContext& ctx);        // /api/slice
std::string api_slice_point(const std::string& body, const ApiContext& ctx);  // /api/slice_point
std::string api_albedo(const std::string& body, const ApiContext& ctx);       // /api/albedo
std::string api_fresnel(const std::string& body, const ApiContext& ctx);      // /api/fresnel
std::string api_check(const std::string& body, const ApiContext& ctx);        // /api/check
// A sphere of the material rendered by gonio render's path tracer under a movable point
// light and a uniform environment: one pass of `spp` samples per pixel with `seed`, linear
// RGB (the page averages passes and tone-maps).
std::string api_sphere(const std::string& body, const ApiContext& ctx);       // /api/sphere
// `gonio fit` of a MERL table in --data: {"file", "model", "distribution", "metric",
// "stride"} -> {"material", "measured", "error", "metric", "evaluations", "seconds"}.
std::string api_fit(const std::string& body, const ApiContext& ctx);          // /api/fit
// The models api_fit takes, a JSON array (empty without Ceres).
std::string api_fit_models();

// Request bounds (a larger request is a 400): the server stays responsive for everyone.
inline constexpr int kMaxLobeCount = 2001;
inline constexpr int kMaxLobe3dTheta = 90, kMaxLobe3dPhi = 360;
inline constexpr int kMaxSliceSize = 512;
inline constexpr int kMaxAlbedoCount = 91;
inline constexpr long long kMaxAlbedoSamples = 1 << 20;
inline constexpr int kMaxFresnelCount = 1801;
inline constexpr long long kMaxEvalPairs = 100000;
inline constexpr int kMaxSphereSize = 256;
inline constexpr int kMaxSphereSpp = 64;

}  // namespace gonio::explore
