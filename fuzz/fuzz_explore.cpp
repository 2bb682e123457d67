// libFuzzer target: the request bodies of gonio explore's JSON API (src/explore/api.h).
// Input: one byte choosing the endpoint (validate, eval, lobe, slice, slice_point,
// albedo, fresnel, lobe3d), then the body. Bodies that parse have their work bounded (counts,
// sizes and samples made small) so that an input runs in milliseconds; the rest go in as
// they are. Only InputError may escape (the server answers it with 400), and every answer
// must be JSON.

#include <cstdint>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "explore/api.h"
#include "gonio/error.h"

namespace {

using Endpoint = std::string (*)(const std::string&, const gonio::explore::ApiContext&);
const Endpoint kEndpoints[] = {&gonio::explore::api_validate, &gonio::explore::api_eval,
                               &gonio::explore::api_lobe,     &gonio::explore::api_slice,
                               &gonio::explore::api_slice_point, &gonio::explore::api_albedo,
                               &gonio::explore::api_fresnel, &gonio::explore::api_lobe3d};

// Keeps the fuzzer fast: the limits the server enforces are tested by the unit tests.
void bound_work(nlohmann::json& b) {
  const auto cap = [&](const char* key, double most) {
    const auto it = b.find(key);
    if (it != b.end() && it->is_number() && it->get<double>() > most) *it = most;
  };
  cap("count", 8);
  cap("samples", 64);
  cap("size", 16);
  cap("count_theta", 6);
  cap("count_phi", 8);
  const auto pairs = b.find("pairs");
  if (pairs != b.end() && pairs->is_array() && pairs->size() > 64) pairs->erase(pairs->begin() + 64, pairs->end());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const Endpoint endpoint = kEndpoints[data[0] % (sizeof kEndpoints / sizeof kEndpoints[0])];
  std::string body(reinterpret_cast<const char*>(data + 1), size - 1);
  nlohmann::json parsed = nlohmann::json::parse(body, nullptr, false);
  if (!parsed.is_discarded() && parsed.is_object()) {
    bound_work(parsed);
    body = parsed.dump();
  }
  const gonio::explore::ApiContext ctx;  // no --data: every file name must be refused
  std::string answer;
  try {
    answer = endpoint(body, ctx);
  } catch (const gonio::InputError&) {
    return 0;
  }
  if (nlohmann::json::parse(answer, nullptr, false).is_discarded()) std::abort();  // not JSON
  return 0;
}
