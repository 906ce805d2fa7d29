// btgen runtime: scenario-driven leaves (tests/conformance/FORMAT.md).
//
// A scenario file says what every user leaf returns, call by call:
//
//     ticks 20                       # most root ticks to send (default 100)
//     default SUCCESS                # what unlisted leaves return
//     leaf FindBall FAILURE SUCCESS  # successive results of the leaf named FindBall
//     clock_ms 100                   # virtual time per tick (default 0)
//     queue Parse waypoints a b c    # every run of Parse first sets its queue port
//                                    # `waypoints` to a new queue of a, b, c
//
// Reading a scenario allocates (it happens before the run); the per-tick
// calls of ScenarioLeaves do not. Problems are reported as
// `path:line:col: error: message` (or `warning:`), with the same wording as
// the Python reference (btgen/interp/scenario.py).
#pragma once

#include <array>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "btgen/harness/scenario_run.hpp"
#include "btgen/node.hpp"
#include "btgen/one_line.hpp"
#include "btgen/status.hpp"

namespace btgen {

struct Diagnostic {
  std::string path;
  long line = 1;
  long col = 1;
  bool error = true;
  std::string message;

  [[nodiscard]] std::string str() const {
    std::string s =
        path + ":" + std::to_string(line) + ":" + std::to_string(col) + (error ? ": error: " : ": warning: ");
    one_line(message, [&s](std::string_view part) { s.append(part); });  // the interpreter's escaping
    return s;
  }
};

struct ScenarioLeaf {
  std::string name;
  std::vector<Status> statuses;
  long line = 1;
  long col = 1;
  std::vector<long> status_cols;  // same line as the name
};

// Whether `leaf.set_queue_port(port, items)` is a call ScenarioLeaves::fill can make.
template <class Leaf, class = void>
struct has_queue_ports : std::false_type {};
template <class Leaf>
struct has_queue_ports<Leaf, std::void_t<decltype(std::declval<Leaf&>().set_queue_port(
                                 std::string_view{}, std::declval<const std::vector<std::string>&>()))>>
    : std::true_type {};

struct ScenarioQueue {
  std::string name;
  std::string port;
  std::vector<std::string> items;
  long line = 1;
  long col = 1;
};

struct Scenario {
  std::string path;
  std::vector<ScenarioQueue> queues;
  long ticks = 100;
  Status default_status = Status::SUCCESS;
  long clock_ms = 0;
  std::vector<ScenarioLeaf> leaves;
  bool has_default_loc = false;
  long default_line = 1;
  long default_col = 1;

  [[nodiscard]] const ScenarioLeaf* leaf(std::string_view name) const {
    for (const auto& l : leaves) {
      if (l.name == name) return &l;
    }
    return nullptr;
  }
};

namespace scenario_detail {

struct Token {
  std::string_view text;
  long col;
};

// Columns count characters (UTF-8 code points), as the Python reference does.
inline long column_of(std::string_view line, std::size_t byte) {
  long col = 1;
  for (std::size_t i = 0; i < byte && i < line.size(); ++i) {
    if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) ++col;
  }
  return col;
}

inline long text_width(std::string_view s) { return column_of(s, s.size()) - 1; }

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

inline std::vector<Token> tokens(std::string_view line) {
  const std::size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) out.push_back(Token{line.substr(start, i - start), column_of(line, start)});
  }
  return out;
}

inline bool parse_status(std::string_view s, Status& out) {
  if (s == "SUCCESS") {
    out = Status::SUCCESS;
    return true;
  }
  if (s == "FAILURE") {
    out = Status::FAILURE;
    return true;
  }
  if (s == "RUNNING") {
    out = Status::RUNNING;
    return true;
  }
  return false;
}

// Levenshtein distance, for "did you mean" hints.
inline std::size_t distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      std::size_t best = diag + cost;
      if (up + 1 < best) best = up + 1;
      if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
      row[j] = best;
      diag = up;
    }
  }
  return row[b.size()];
}

inline std::string upper(std::string_view s) {
  std::string out(s);
  for (auto& c : out) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  }
  return out;
}

// The closest candidate (same letters in another case, or at most a third
// of the letters different), or "" when nothing is close.
inline std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  for (const auto& c : candidates) {
    if (c != word && upper(c) == upper(word)) return c;
  }
  std::string best;
  std::size_t best_d = 0;
  for (const auto& c : candidates) {
    const std::size_t d = distance(word, c);
    const std::size_t limit = (word.size() > c.size() ? word.size() : c.size()) / 3;
    if (d > 0 && d <= limit && (best.empty() || d < best_d)) {
      best = c;
      best_d = d;
    }
  }
  return best;
}

inline std::string status_error(std::string_view tok) {
  if (tok == "SKIPPED") return "`SKIPPED` cannot be scripted: a leaf returns SUCCESS, FAILURE or RUNNING";
  if (tok == "IDLE") return "`IDLE` cannot be scripted: a leaf returns SUCCESS, FAILURE or RUNNING";
  const std::vector<std::string> statuses{"SUCCESS", "FAILURE", "RUNNING"};
  std::string hint = did_you_mean(upper(tok), statuses);
  std::string msg = "unknown status `" + std::string(tok) + "`: use SUCCESS, FAILURE or RUNNING";
  if (!hint.empty()) msg += " (did you mean `" + hint + "`?)";
  return msg;
}

// A whole number as the reference reads it: [+-]?[0-9]+, with its value
// saturated to +-2^62 so that "too large" can be told.
inline bool parse_whole(std::string_view s, long long& value, std::string& shown) {
  std::size_t i = 0;
  bool neg = false;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    neg = s[0] == '-';
    i = 1;
  }
  if (i == s.size()) return false;
  long long v = 0;
  const long long cap = 1LL << 62;
  std::string digits;
  for (; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    if (!(digits.empty() && s[i] == '0')) digits += s[i];
    v = v <= (cap - 9) / 10 ? v * 10 + (s[i] - '0') : cap;  // saturate: no signed overflow
  }
  if (v > cap) v = cap;
  if (digits.empty()) digits = "0";
  value = neg ? -v : v;
  shown = (neg && digits != "0" ? "-" : "") + digits;
  return true;
}

}  // namespace scenario_detail

class ScenarioParser {
 public:
  ScenarioParser(std::string path, std::vector<Diagnostic>& diags) : path_(std::move(path)), diags_(diags) {}

  // Parses `text` into `out`; false when there was an error.
  bool parse(std::string_view text, Scenario& out) {
    using scenario_detail::Token;
    const std::size_t errors_before = error_count();
    out = Scenario{};
    out.path = path_;
    long ticks_line = 0, default_line = 0, clock_line = 0;
    bool have_ticks = false, have_clock = false;
    long lineno = 0;
    std::size_t start = 0;
    while (start <= text.size()) {
      std::size_t end = text.find('\n', start);
      if (end == std::string_view::npos) end = text.size();
      std::string_view line = text.substr(start, end - start);
      start = end + 1;
      ++lineno;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      const std::vector<Token> toks = scenario_detail::tokens(line);
      if (toks.empty()) continue;
      const Token& kw = toks[0];
      const std::vector<Token> args(toks.begin() + 1, toks.end());
      const long after_kw = kw.col + scenario_detail::text_width(kw.text);
      if (kw.text == "ticks") {
        if (ticks_line != 0) {
          error(lineno, kw.col, "`ticks` is given twice (first at line " + std::to_string(ticks_line) + ")");
          continue;
        }
        ticks_line = lineno;
        long long v = 0;
        if (one_int(lineno, kw, after_kw, args, "ticks", "the most root ticks to send", v)) {
          if (v < 1) {
            error(lineno, args[0].col, "ticks must be at least 1, got " + shown_);
          } else {
            out.ticks = static_cast<long>(v);
            have_ticks = true;
          }
        }
      } else if (kw.text == "default") {
        if (default_line != 0) {
          error(lineno, kw.col, "`default` is given twice (first at line " + std::to_string(default_line) + ")");
          continue;
        }
        default_line = lineno;
        if (args.empty()) {
          error(lineno, after_kw, "`default` needs a status: SUCCESS, FAILURE or RUNNING");
          continue;
        }
        if (args.size() > 1) {
          error(lineno, args[1].col, "`default` takes one status, found also `" + std::string(args[1].text) + "`");
        }
        Status s{};
        if (scenario_detail::parse_status(args[0].text, s)) {
          out.default_status = s;
          out.has_default_loc = true;
          out.default_line = lineno;
          out.default_col = args[0].col;
        } else {
          error(lineno, args[0].col, scenario_detail::status_error(args[0].text));
        }
      } else if (kw.text == "clock_ms") {
        if (clock_line != 0) {
          error(lineno, kw.col, "`clock_ms` is given twice (first at line " + std::to_string(clock_line) + ")");
          continue;
        }
        clock_line = lineno;
        long long v = 0;
        if (one_int(lineno, kw, after_kw, args, "clock_ms", "the milliseconds the clock advances before each tick",
                    v)) {
          if (v < 0) {
            error(lineno, args[0].col, "clock_ms cannot be negative, got " + shown_);
          } else {
            out.clock_ms = static_cast<long>(v);
            have_clock = true;
          }
        }
      } else if (kw.text == "leaf") {
        if (args.empty()) {
          error(lineno, after_kw, "`leaf` needs a leaf name and at least one status");
          continue;
        }
        const Token& name = args[0];
        if (const ScenarioLeaf* prev = out.leaf(name.text)) {
          error(lineno, name.col,
                "leaf `" + std::string(name.text) + "` is listed twice (first at line " + std::to_string(prev->line) +
                    ")");
          continue;
        }
        if (args.size() == 1) {
          error(lineno, name.col + scenario_detail::text_width(name.text),
                "leaf `" + std::string(name.text) + "` has no status: list one or more of SUCCESS, FAILURE, RUNNING");
          continue;
        }
        ScenarioLeaf leaf;
        leaf.name = std::string(name.text);
        leaf.line = lineno;
        leaf.col = name.col;
        for (std::size_t i = 1; i < args.size(); ++i) {
          Status s{};
          if (!scenario_detail::parse_status(args[i].text, s)) {
            error(lineno, args[i].col, scenario_detail::status_error(args[i].text));
            s = Status::FAILURE;
          }
          leaf.statuses.push_back(s);
          leaf.status_cols.push_back(args[i].col);
        }
        out.leaves.push_back(std::move(leaf));
      } else if (kw.text == "queue") {
        if (args.size() < 2) {
          error(lineno, kw.col, "`queue` needs a leaf name, its queue port and the queue's items (none: empty)");
          continue;
        }
        const ScenarioQueue* prev = nullptr;
        for (const auto& q : out.queues) {
          if (q.name == args[0].text && q.port == args[1].text) prev = &q;
        }
        if (prev != nullptr) {
          error(lineno, args[1].col,
                "queue port `" + std::string(args[1].text) + "` of leaf `" + std::string(args[0].text) +
                    "` is listed twice (first at line " + std::to_string(prev->line) + ")");
          continue;
        }
        ScenarioQueue q;
        q.name = std::string(args[0].text);
        q.port = std::string(args[1].text);
        for (std::size_t i = 2; i < args.size(); ++i) q.items.emplace_back(args[i].text);
        q.line = lineno;
        q.col = args[0].col;
        out.queues.push_back(std::move(q));
      } else {
        std::string msg = "unknown keyword `" + std::string(kw.text) +
                          "`: a line starts with ticks, default, leaf, clock_ms or queue";
        const std::string hint =
            scenario_detail::did_you_mean(kw.text, {"ticks", "default", "leaf", "clock_ms", "queue"});
        if (!hint.empty()) msg += " (did you mean `" + hint + "`?)";
        error(lineno, kw.col, msg);
      }
    }
    (void)have_ticks;
    (void)have_clock;
    return error_count() == errors_before;
  }

 private:
  std::size_t error_count() const {
    std::size_t n = 0;
    for (const auto& d : diags_) n += d.error ? 1u : 0u;
    return n;
  }

  void error(long line, long col, std::string msg) {
    diags_.push_back(Diagnostic{path_, line, col, true, std::move(msg)});
  }

  bool one_int(long line, const scenario_detail::Token& kw, long after_kw,
               const std::vector<scenario_detail::Token>& args, const char* what, const char* meaning,
               long long& value) {
    const std::string w(what);
    if (args.empty()) {
      error(line, after_kw, "`" + w + "` needs a whole number (" + meaning + ")");
      return false;
    }
    (void)kw;
    if (args.size() > 1) {
      error(line, args[1].col, "`" + w + "` takes one number, found also `" + std::string(args[1].text) + "`");
      return false;
    }
    if (!scenario_detail::parse_whole(args[0].text, value, shown_)) {
      error(line, args[0].col, "`" + w + "` needs a whole number, got `" + std::string(args[0].text) + "`");
      return false;
    }
    if (value > 2147483647LL) {
      error(line, args[0].col, w + " " + shown_ + " is too large (at most 2147483647)");
      return false;
    }
    return true;
  }

  std::string path_;
  std::vector<Diagnostic>& diags_;
  std::string shown_;
};

// Reads and parses a scenario file (UTF-8, an optional BOM).
inline bool read_scenario(const std::string& path, Scenario& out, std::vector<Diagnostic>& diags) {
  constexpr std::size_t kMaxBytes = 16u * 1024u * 1024u;
  auto fail = [&](long line, long col, std::string msg) {
    diags.push_back(Diagnostic{path, line, col, true, std::move(msg)});
    return false;
  };
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return fail(1, 1, std::string("cannot read scenario: ") + std::strerror(errno));
  std::string data;
  char buf[65536];
  for (;;) {
    const std::size_t n = std::fread(buf, 1, sizeof buf, f);
    data.append(buf, n);
    if (data.size() > kMaxBytes) {
      std::fclose(f);
      return fail(1, 1,
                  "file is larger than " + std::to_string(kMaxBytes) + " bytes; scenarios are limited to " +
                      std::to_string(kMaxBytes) + " bytes");
    }
    if (n < sizeof buf) break;
  }
  const bool read_error = std::ferror(f) != 0;
  const int err = errno;
  std::fclose(f);
  if (read_error) {
    if (err == EISDIR) return fail(1, 1, "is a directory, not a scenario file");
    return fail(1, 1, std::string("cannot read scenario: ") + std::strerror(err));
  }
  std::string_view text(data);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  // Validate UTF-8.
  long line = 1, col = 1;
  for (std::size_t i = 0; i < text.size();) {
    const auto b = static_cast<unsigned char>(text[i]);
    std::size_t len = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 0;
    bool ok = len != 0 && i + len <= text.size();
    for (std::size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    if (ok && len > 1) {
      // Reject overlong forms, surrogates and values past U+10FFFF.
      std::uint32_t cp = b & (0xFF >> (len + 1));
      for (std::size_t k = 1; k < len; ++k) cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3F);
      const std::uint32_t min[] = {0, 0, 0x80, 0x800, 0x10000};
      ok = cp >= min[len] && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
    }
    if (!ok) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", b);
      return fail(line, col, std::string("invalid UTF-8 (byte ") + hex + "); scenarios must be UTF-8");
    }
    if (b == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
    i += len;
  }
  return ScenarioParser(path, diags).parse(text, out);
}

// The checks that need the mission: no Condition may return RUNNING (error),
// a `leaf` line naming no user leaf of the mission is ignored (warning).
// `unrun` lists {name, tree} of leaves only in trees the main tree `main_tree`
// does not run (the generated class's unrun_leaves()), for a sharper warning.
inline bool check_scenario(const Scenario& sc, const NodeInfo* nodes, std::size_t count, std::vector<Diagnostic>& diags,
                           const std::array<std::string_view, 2>* unrun = nullptr, std::size_t unrun_count = 0,
                           std::string_view main_tree = {}) {
  bool ok = true;
  std::vector<std::string> leaf_names;
  auto is_user_leaf = [](const NodeInfo& n) { return is_scripted(n.kind); };
  auto is_builtin_leaf = [](const NodeInfo& n) {
    return is_leaf(n.kind) && n.kind != NodeKind::Action && n.kind != NodeKind::Condition;
  };
  auto first_condition = [&](std::string_view name) -> const NodeInfo* {
    for (std::size_t i = 0; i < count; ++i) {
      if (is_condition_like(nodes[i].kind) && nodes[i].name == name) return &nodes[i];
    }
    return nullptr;
  };
  for (std::size_t i = 0; i < count; ++i) {
    if (!is_user_leaf(nodes[i])) continue;
    bool seen = false;
    for (const auto& s : leaf_names) seen = seen || s == nodes[i].name;
    if (!seen) leaf_names.emplace_back(nodes[i].name);
  }
  for (const auto& leaf : sc.leaves) {
    bool found = false;
    for (const auto& s : leaf_names) found = found || s == leaf.name;
    if (!found) {
      bool builtin = false;
      for (std::size_t i = 0; i < count; ++i)
        builtin = builtin || (is_builtin_leaf(nodes[i]) && nodes[i].name == leaf.name);
      const std::array<std::string_view, 2>* elsewhere = nullptr;
      for (std::size_t k = 0; k < unrun_count && elsewhere == nullptr; ++k) {
        if (unrun[k][0] == leaf.name) elsewhere = &unrun[k];
      }
      if (builtin) {
        diags.push_back(Diagnostic{sc.path, leaf.line, leaf.col, false,
                                   "`" + leaf.name +
                                       "` is a built-in node of BehaviorTree.CPP and keeps its built-in behaviour; "
                                       "its line is ignored"});
      } else if (elsewhere != nullptr) {
        diags.push_back(Diagnostic{sc.path, leaf.line, leaf.col, false,
                                   "leaf `" + leaf.name + "` is only in BehaviorTree `" + std::string((*elsewhere)[1]) +
                                       "`, which the main tree `" + std::string(main_tree) +
                                       "` does not run; its line is ignored"});
      } else {
        std::string msg = "leaf `" + leaf.name + "` matches no Action or Condition of the mission; its line is ignored";
        const std::string hint = scenario_detail::did_you_mean(leaf.name, leaf_names);
        if (!hint.empty()) msg += " (did you mean `" + hint + "`?)";
        diags.push_back(Diagnostic{sc.path, leaf.line, leaf.col, false, std::move(msg)});
      }
      continue;
    }
    if (const NodeInfo* cond = first_condition(leaf.name)) {
      for (std::size_t k = 0; k < leaf.statuses.size(); ++k) {
        if (leaf.statuses[k] == Status::RUNNING && cond->kind != NodeKind::Condition) {
          diags.push_back(Diagnostic{sc.path, leaf.line, leaf.status_cols[k], true,
                                     "`" + leaf.name + "` scripts the input of Nav2's `" + std::string(cond->id) +
                                         "` at " + std::string(cond->source) +
                                         ": SUCCESS for yes or FAILURE for no, not RUNNING"});
          ok = false;
          break;
        }
        if (leaf.statuses[k] == Status::RUNNING) {
          diags.push_back(Diagnostic{sc.path, leaf.line, leaf.status_cols[k], true,
                                     "`" + leaf.name +
                                         "` is a Condition and cannot return RUNNING (a Condition answers in one "
                                         "tick; its Condition node is at " +
                                         std::string(cond->source) + ")"});
          ok = false;
          break;
        }
      }
    }
  }
  if (sc.default_status == Status::RUNNING) {
    for (const auto& name : leaf_names) {
      const NodeInfo* cond = first_condition(name);
      if (cond == nullptr || sc.leaf(name) != nullptr) continue;
      diags.push_back(
          Diagnostic{sc.path, sc.has_default_loc ? sc.default_line : 1, sc.has_default_loc ? sc.default_col : 1, true,
                     "`default RUNNING` reaches the Condition `" + name + "` (at " + std::string(cond->source) +
                         "), which cannot return RUNNING; give it its own `leaf " + name + " ...` line"});
      ok = false;
    }
  }
  return ok;
}

// Leaves whose results come from a scenario. All instances with one name
// share one list; a used-up list repeats its last status. Generic hooks
// (ScenarioHooks), so one object serves every leaf model of any mission.
class ScenarioLeaves : public ScenarioHooks<ScenarioLeaves> {
 public:
  ScenarioLeaves(const Scenario& sc, const NodeInfo* nodes, std::size_t count)
      : list_of_node_(count, kNone), default_(sc.default_status) {
    for (const auto& leaf : sc.leaves) lists_.push_back(List{leaf.statuses, 0});
    for (std::size_t i = 0; i < count; ++i) {
      if (!is_scripted(nodes[i].kind)) continue;
      for (std::size_t k = 0; k < sc.leaves.size(); ++k) {
        if (sc.leaves[k].name == nodes[i].name) list_of_node_[i] = static_cast<std::uint32_t>(k);
      }
      for (const auto& q : sc.queues) {
        if (q.name == nodes[i].name) fills_.push_back(Fill{static_cast<std::uint32_t>(i), &q});
      }
    }
  }

 private:
  friend class ScenarioHooks<ScenarioLeaves>;

  // The `queue` lines of each node, in node order.
  struct Fill {
    std::uint32_t node;
    const ScenarioQueue* queue;
  };

 public:
  // A leaf that has queue ports (a generated model, btgen::UserNode) gets each of its
  // `queue` lines; any other object a caller checks with (the Lab Tour's robot passes an
  // int: only the node is looked at) has none to fill.
  template <class Leaf>
  void fill(Leaf& leaf, const NodeInfo& node) noexcept {
    if constexpr (has_queue_ports<Leaf>::value) {
      for (const Fill& f : fills_) {
        if (f.node == node.index) (void)leaf.set_queue_port(f.queue->port, f.queue->items);
      }
    } else {
      (void)leaf;
      (void)node;
    }
  }

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  struct List {
    std::vector<Status> statuses;
    std::size_t cursor;
  };

  Status next(const NodeInfo& node) noexcept {
    const std::uint32_t k = list_of_node_[node.index];
    if (k == kNone) return default_;
    List& l = lists_[k];
    const Status s = l.statuses[l.cursor < l.statuses.size() ? l.cursor : l.statuses.size() - 1];
    if (l.cursor < l.statuses.size()) ++l.cursor;
    return s;
  }

  std::vector<std::uint32_t> list_of_node_;
  std::vector<List> lists_;
  std::vector<Fill> fills_;
  Status default_;
};

}  // namespace btgen
