// What a fleet benchmark reads back from the files its child processes wrote: a whole log, a
// coordinator's --json summary, the safety monitor's count of overlaps.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace coordinator {

// The file's whole text; "" when it cannot be read.
std::string read_file(const std::string& path);

// The coordinator's --json summary (its whole stdout); an empty object when it wrote none.
nlohmann::json read_summary(const std::string& path);

// The overlaps (robots on one cell at once) the safety monitor's log reports, "-" when it reports
// none (it did not finish).
std::string monitor_overlaps(const std::string& monitor_log_text);

}  // namespace coordinator
