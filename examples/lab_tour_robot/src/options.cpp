#include "options.hpp"

#include <cctype>

#include "speech.hpp"

namespace lab_tour_robot {

namespace {

bool parse_count(std::string_view text, long low, long high, long& out) {
  if (text.empty() || text.size() > 12) return false;
  long long v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  if (v < low || v > high) return false;
  out = static_cast<long>(v);
  return true;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::string usage_text(std::string_view program) {
  std::string p(program);
  return "usage: " + p +
         " [--language English|isiZulu|Kinyarwanda] [--kb-config FILE.ini]\n"
         "       " +
         std::string(p.size(), ' ') +
         " [--answer yes|no] [--scenario FILE.scenario] [--trace]\n"
         "       " +
         std::string(p.size(), ' ') +
         " [--tick-ms N] [--max-ticks N] [--groot2 PORT] [--groot2-address ADDR]\n"
         "       " +
         std::string(p.size(), ' ') +
         " [--linger-ms N] [--btlog FILE.btlog]\n"
         "\n"
         "Runs the Lab Tour mission (missions/LabTour.xml, compiled by btgen) on a\n"
         "simulated Pepper that takes poses, gesture targets and messages from the\n"
         "environment knowledge base.\n"
         "\n"
         "  --language L        language of the robot's speech (default English); a text\n"
         "                      without a translation is said in English after a\n"
         "                      \"[no L translation]\" marker\n"
         "  --kb-config FILE    knowledge base configuration (default\n"
         "                      data/environmentKnowledgeBaseConfiguration.ini, looked up\n"
         "                      in the current folder, then in the btgen repository);\n"
         "                      its knowledgeBase is relative to the .ini's folder\n"
         "  --answer yes|no     the visitor's answer to \"would you like the tour?\"\n"
         "                      (default yes, or what --scenario scripts)\n"
         "  --scenario FILE     take every leaf's status from a scenario file\n"
         "                      (btgen's tests/conformance/FORMAT.md) instead of the\n"
         "                      simulation; its `ticks` is the default --max-ticks\n"
         "  --trace             also print the status trace (FORMAT.md): the lines that\n"
         "                      do not start with \"[tick\" or \"lab_tour_robot:\"\n"
         "  --tick-ms N         sleep N ms between ticks, for a live demo (default 0)\n"
         "  --max-ticks N       give up (halt, exit 1) after N ticks (default 10000)\n"
         "  --groot2 PORT       publish the run to Groot2 (BehaviorTree.CPP's Groot2Publisher\n"
         "                      protocol on PORT and PORT+1, all interfaces); use with\n"
         "                      --tick-ms to watch it live; the blackboards' names are\n"
         "                      listed at the start\n"
         "  --groot2-address A  the interface the publisher binds (default *: all;\n"
         "                      127.0.0.1: this machine only)\n"
         "  --linger-ms N       with --groot2: keep publishing N ms after the mission\n"
         "                      ends, so Groot2 and btview show its last statuses\n"
         "                      (default 3000; 0: exit at once)\n"
         "  --btlog FILE        write a Groot2 log file (FileLogger2 .btlog) of the run;\n"
         "                      only Groot2 replays it (`btgen graph --btlog` draws it)\n"
         "\n"
         "Exit status: 0 the mission ended SUCCESS, 1 it ended FAILURE or ran out of\n"
         "ticks, 2 bad options, knowledge base or scenario.\n";
}

bool parse_options(int argc, const char* const* argv, Options& out, std::string& error) {
  out = Options{};
  bool seen_language = false, seen_tick_ms = false, seen_scenario = false, seen_trace = false;
  bool seen_groot2 = false, seen_btlog = false, seen_address = false, seen_linger = false;
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      out.help = true;
      continue;
    }
    if (arg.substr(0, 2) != "--") {
      error = "unexpected argument `" + std::string(arg) + "` (options start with --)";
      return false;
    }
    std::string_view name = arg;
    std::string_view value;
    bool has_value = false;
    const std::size_t eq = arg.find('=');
    if (eq != std::string_view::npos) {
      name = arg.substr(0, eq);
      value = arg.substr(eq + 1);
      has_value = true;
    }
    const bool flag = name == "--trace";
    const bool known = flag || name == "--language" || name == "--kb-config" || name == "--answer" ||
                       name == "--scenario" || name == "--tick-ms" || name == "--max-ticks" || name == "--groot2" ||
                       name == "--btlog" || name == "--groot2-address" || name == "--linger-ms";
    if (!known) {
      error = "unknown option `" + std::string(name) + "`";
      return false;
    }
    if (flag) {
      if (has_value) {
        error = "`--trace` takes no value";
        return false;
      }
      if (seen_trace) {
        error = "`--trace` is given twice";
        return false;
      }
      seen_trace = out.trace = true;
      continue;
    }
    if (!has_value) {
      if (i + 1 >= argc) {
        error = "`" + std::string(name) + "` needs a value";
        return false;
      }
      value = argv[++i];
    }
    auto twice = [&](bool& seen) {
      if (seen) error = "`" + std::string(name) + "` is given twice";
      const bool was = seen;
      seen = true;
      return was;
    };
    if (name == "--language") {
      if (twice(seen_language)) return false;
      if (!parse_language(value, out.language)) {
        error = "unknown language `" + std::string(value) + "`: use English, isiZulu or Kinyarwanda";
        return false;
      }
    } else if (name == "--kb-config") {
      if (twice(out.kb_config_given)) return false;
      if (value.empty()) {
        error = "`--kb-config` needs a file name";
        return false;
      }
      out.kb_config = std::string(value);
    } else if (name == "--answer") {
      if (twice(out.answer_given)) return false;
      const std::string v = lower(value);
      if (v != "yes" && v != "no") {
        error = "`--answer` is yes or no, not `" + std::string(value) + "`";
        return false;
      }
      out.answer_yes = v == "yes";
    } else if (name == "--scenario") {
      if (twice(seen_scenario)) return false;
      if (value.empty()) {
        error = "`--scenario` needs a file name";
        return false;
      }
      out.scenario = std::string(value);
    } else if (name == "--tick-ms") {
      if (twice(seen_tick_ms)) return false;
      if (!parse_count(value, 0, 60000, out.tick_ms)) {
        error = "`--tick-ms` is a whole number of milliseconds from 0 to 60000, not `" + std::string(value) + "`";
        return false;
      }
    } else if (name == "--groot2") {
      if (twice(seen_groot2)) return false;
      if (!parse_count(value, 1, 65534, out.groot2_port)) {
        error =
            "`--groot2` is a TCP port from 1 to 65534 (it also uses the next one), not `" + std::string(value) + "`";
        return false;
      }
    } else if (name == "--groot2-address") {
      if (twice(seen_address)) return false;
      if (value.empty() || value.find_first_of(" /:") != std::string_view::npos) {
        error = "`--groot2-address` is an interface address such as 127.0.0.1 or *, not `" + std::string(value) + "`";
        return false;
      }
      out.groot2_address = std::string(value);
    } else if (name == "--linger-ms") {
      if (twice(seen_linger)) return false;
      if (!parse_count(value, 0, 600000, out.linger_ms)) {
        error = "`--linger-ms` is a whole number of milliseconds from 0 to 600000, not `" + std::string(value) + "`";
        return false;
      }
    } else if (name == "--btlog") {
      if (twice(seen_btlog)) return false;
      if (value.size() < 7 || value.substr(value.size() - 6) != ".btlog") {
        error = "`--btlog` needs a file name ending in .btlog, not `" + std::string(value) + "`";
        return false;
      }
      out.btlog = std::string(value);
    } else if (name == "--max-ticks") {
      if (twice(out.max_ticks_given)) return false;
      if (!parse_count(value, 1, 1000000000, out.max_ticks)) {
        error = "`--max-ticks` is a whole number from 1 to 1000000000, not `" + std::string(value) + "`";
        return false;
      }
    }
  }
  return true;
}

}  // namespace lab_tour_robot
