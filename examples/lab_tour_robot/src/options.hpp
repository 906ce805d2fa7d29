// The command line of lab_tour_robot.
#pragma once

#include <string>
#include <string_view>

#include "btgen/environment_knowledge_base.hpp"

namespace lab_tour_robot {

inline constexpr std::string_view kDefaultKbConfig = "data/environmentKnowledgeBaseConfiguration.ini";
inline constexpr long kDefaultMaxTicks = 10000;
inline constexpr long kDefaultLingerMs = 3000;

struct Options {
  btgen::Language language = btgen::Language::kEnglish;
  std::string kb_config{kDefaultKbConfig};
  bool kb_config_given = false;
  bool answer_given = false;
  bool answer_yes = true;
  std::string scenario;  ///< empty: no scenario
  bool trace = false;
  long tick_ms = 0;
  long max_ticks = kDefaultMaxTicks;
  bool max_ticks_given = false;
  long groot2_port = 0;               ///< 0: no Groot2 publisher
  std::string groot2_address = "*";   ///< the interface the publisher binds ("*": all)
  long linger_ms = kDefaultLingerMs;  ///< with --groot2: how long the publisher stays up after the end
  std::string btlog;                  ///< empty: no .btlog
  bool help = false;
};

/// Parses argv; on a mistake returns false with a one-line `error`.
/// Accepts `--name value` and `--name=value`.
[[nodiscard]] bool parse_options(int argc, const char* const* argv, Options& out, std::string& error);

/// The --help text.
[[nodiscard]] std::string usage_text(std::string_view program);

}  // namespace lab_tour_robot
