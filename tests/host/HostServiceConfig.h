#pragma once
// The service configuration the host tests drive: the built-in terrain of 512² voxels at 2 m (a
// 1 km square) cached in `dir`/cache, a 320 × 240 grey progressive output at 59.94 Hz rendered by
// two workers, the ownship from a CIGI host on 127.0.0.1:`port`, the summary in out/summary.json,
// the field thread at ordinary priority. `more` is appended (further tables: sinks, more metrics).

#include <cstdint>
#include <filesystem>
#include <string>

namespace fieldcast::testing {

inline std::string hostServiceConfig(const std::filesystem::path& dir, std::uint16_t port, const std::string& more = "",
                                     const std::string& moreMetrics = "") {
  return "[terrain]\nsource = \"builtin\"\ncache_dir = \"" + (dir / "cache").string() +
         "\"\nbuiltin_size = 512\nmemory_budget_mb = 64\n"
         "[render]\nthreads = 2\n"
         "[output]\nrate = 59.94\nscan = \"progressive\"\nwidth = 320\nheight = 240\nformat = \"grey8\"\n"
         "[motion]\nsource = \"host\"\nstart = [500.0, 500.0, 400.0, 0.0]\n"
         "[host]\nport = " +
         std::to_string(port) + "\n[metrics]\nsummary_json = \"out/summary.json\"\n" + moreMetrics +
         "[threads]\nrealtime_field_thread = false\n" + more;
}

}  // namespace fieldcast::testing
