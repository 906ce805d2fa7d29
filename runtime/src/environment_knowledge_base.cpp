// Reader of the environment knowledge base; see environment_knowledge_base.hpp
// and data/README.md. The rules mirror generator/btgen/kb/lint.py and the schema
// schema/environment_knowledge_base.xsd, and the messages are the linter's,
// so a robot and `btgen lint-kb` point at the same line and column.
#include "btgen/environment_knowledge_base.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <ostream>
#include <string_view>
#include <system_error>
#include <tuple>

namespace btgen {
namespace {

namespace fs = std::filesystem;
using kb_limits::kMaxAbsCoordinate;
using kb_limits::kMaxCulturalKeyBytes;
using kb_limits::kMaxCulturalKeys;
using kb_limits::kMaxFileBytes;
using kb_limits::kMaxLocationId;
using kb_limits::kMaxTextBytes;
using kb_limits::kMaxTourLocations;

// ----- Keys ---------------------------------------------------------------------

enum class Kind { kText, kPoint, kCultural, kTour };

struct KeyInfo {
  std::string_view name;
  Kind kind;
  std::string_view coordinates;  // point keys: "x y theta" / "x y z"
};

// The ten location keys in schema order, then the tour.
constexpr std::array<KeyInfo, 11> kKeys = {{
    {"robotLocationDescription", Kind::kText, ""},
    {"robotLocationPose", Kind::kPoint, "x y theta"},
    {"gestureTarget", Kind::kPoint, "x y z"},
    {"preGestureMessageEnglish", Kind::kText, ""},
    {"preGestureMessageIsiZulu", Kind::kText, ""},
    {"preGestureMessageKinyarwanda", Kind::kText, ""},
    {"postGestureMessageEnglish", Kind::kText, ""},
    {"postGestureMessageIsiZulu", Kind::kText, ""},
    {"postGestureMessageKinyarwanda", Kind::kText, ""},
    {"culturalKnowledge", Kind::kCultural, ""},
    {"tourSpecification", Kind::kTour, ""},
}};
constexpr std::size_t kLocationKeyCount = 10;

int keyIndex(std::string_view name) {
  for (std::size_t i = 0; i < kKeys.size(); ++i) {
    if (kKeys[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

std::string str(std::string_view s) { return std::string(s); }

std::string backticked(std::string_view s) { return "`" + str(s) + "`"; }

std::string describeValues(const KeyInfo& key) {
  switch (key.kind) {
    case Kind::kPoint: return "a location id and 3 numbers (" + str(key.coordinates) + ")";
    case Kind::kCultural:
      return "a location id and 1 to " + std::to_string(kMaxCulturalKeys) + " cultural knowledge keys";
    case Kind::kTour: return "the number of locations, then their ids in visiting order";
    case Kind::kText: break;
  }
  return "a location id and a text";
}

// ----- Lexical rules (the schema's patterns) ------------------------------------

bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isBlank(char c) { return c == ' ' || c == '\t'; }

/// [1-9][0-9]* and at most kMaxLocationId.
std::optional<std::int32_t> parseLocationId(std::string_view s) {
  if (s.empty() || s[0] == '0' || s.size() > 10) return std::nullopt;
  std::int64_t value = 0;
  for (char c : s) {
    if (!isDigit(c)) return std::nullopt;
    value = value * 10 + (c - '0');
  }
  if (value > kMaxLocationId) return std::nullopt;
  return static_cast<std::int32_t>(value);
}

/// 0|[1-9][0-9]*, any size; nullopt when malformed, a saturated value when huge.
std::optional<std::uint64_t> parseCount(std::string_view s) {
  if (s.empty() || (s[0] == '0' && s.size() > 1)) return std::nullopt;
  std::uint64_t value = 0;
  for (char c : s) {
    if (!isDigit(c)) return std::nullopt;
    value = std::min<std::uint64_t>(value * 10 + static_cast<std::uint64_t>(c - '0'), 1000000000u);
  }
  return value;
}

/// [+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)
bool isDecimal(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t int_digits = 0, frac_digits = 0;
  while (i < s.size() && isDigit(s[i])) ++i, ++int_digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && isDigit(s[i])) ++i, ++frac_digits;
  }
  return i == s.size() && (int_digits > 0 || frac_digits > 0);
}

/// Would Python's float() read it (an exponent, INF, NaN)? Only to explain the error.
bool looksLikeOtherFloat(std::string_view s) {
  std::string_view t = s;
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  double ignored = 0.0;
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), ignored);
  if (ec == std::errc() && ptr == t.data() + t.size()) return true;
  std::string l = lower(t);
  if (!l.empty() && l[0] == '-') l.erase(0, 1);
  return l == "inf" || l == "infinity" || l == "nan";
}

/// [A-Za-z][A-Za-z0-9_]*
bool isCulturalKey(std::string_view s) {
  auto alpha = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); };
  if (s.empty() || !alpha(s[0])) return false;
  return std::all_of(s.begin(), s.end(), [&](char c) { return alpha(c) || isDigit(c) || c == '_'; });
}

// ----- Reading lines ----------------------------------------------------------------

struct Line {
  int number = 0;
  std::string text;
  std::vector<int> col;  // col[i]: 1-based column (in characters) of byte i; col[size] = end

  int colAt(std::size_t byte) const { return col[byte]; }
};

/// Diagnostics of one file, sorted by position when taken.
class Reporter {
 public:
  explicit Reporter(std::string path) : path_(std::move(path)) {}

  void error(int line, int col, const std::string& message) {
    items_.push_back(
        {line, col, path_ + ":" + std::to_string(line) + ":" + std::to_string(col) + ": error: " + message});
  }
  bool empty() const { return items_.empty(); }
  const std::string& path() const { return path_; }

  std::vector<std::string> take() {
    std::stable_sort(items_.begin(), items_.end(),
                     [](const Item& a, const Item& b) { return std::tie(a.line, a.col) < std::tie(b.line, b.col); });
    std::vector<std::string> out;
    for (Item& item : items_) {
      if (out.empty() || out.back() != item.text) out.push_back(std::move(item.text));
    }
    items_.clear();
    return out;
  }

 private:
  struct Item {
    int line;
    int col;
    std::string text;
  };
  std::string path_;
  std::vector<Item> items_;
};

/// Length of the well-formed UTF-8 sequence at s[i], or 0 (Unicode Table 3-7).
std::size_t utf8SequenceLength(const std::string& s, std::size_t i) {
  auto byte = [&](std::size_t k) -> unsigned { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0x100u; };
  auto in = [](unsigned b, unsigned lo, unsigned hi) { return b >= lo && b <= hi; };
  const unsigned b0 = byte(i);
  if (b0 < 0x80) return 1;
  if (in(b0, 0xC2, 0xDF)) return in(byte(i + 1), 0x80, 0xBF) ? 2 : 0;
  unsigned lo = 0x80, hi = 0xBF;
  if (b0 == 0xE0) lo = 0xA0;
  if (b0 == 0xED) hi = 0x9F;
  if (in(b0, 0xE0, 0xEF)) {
    return in(byte(i + 1), lo, hi) && in(byte(i + 2), 0x80, 0xBF) ? 3 : 0;
  }
  if (b0 == 0xF0) lo = 0x90;
  if (b0 == 0xF4) hi = 0x8F;
  if (in(b0, 0xF0, 0xF4)) {
    return in(byte(i + 1), lo, hi) && in(byte(i + 2), 0x80, 0xBF) && in(byte(i + 3), 0x80, 0xBF) ? 4 : 0;
  }
  return 0;
}

std::string hexByte(unsigned char b) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", static_cast<unsigned>(b));
  return buf;
}

std::string codePoint(unsigned char b) {
  char buf[12];
  std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(b));
  return buf;
}

/// The lines of a file, or nullopt after reporting why it cannot be used.
std::optional<std::vector<Line>> readLines(const std::string& path, const char* what, Reporter& r) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    r.error(1, 1, std::string("is a directory, not a ") + what + " file");
    return std::nullopt;
  }
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    r.error(1, 1, std::string("cannot read file: ") + std::strerror(errno != 0 ? errno : ENOENT));
    return std::nullopt;
  }
  std::string data;
  char buf[65536];
  std::size_t n = 0;
  while (data.size() <= kMaxFileBytes && (n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) {
    r.error(1, 1, "cannot read file: input/output error");
    return std::nullopt;
  }
  if (data.size() > kMaxFileBytes) {
    const auto size = fs::file_size(path, ec);
    r.error(1, 1,
            "file is " + (ec ? std::string("more than ") + std::to_string(kMaxFileBytes) : std::to_string(size)) +
                " bytes; " + what + " files are limited to " + std::to_string(kMaxFileBytes) + " bytes");
    return std::nullopt;
  }
  std::size_t start = data.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  std::vector<Line> lines;
  bool ok = true;
  for (int number = 1;; ++number) {
    std::size_t end = data.find('\n', start);
    const bool last = end == std::string::npos;
    Line line;
    line.number = number;
    line.text = data.substr(start, (last ? data.size() : end) - start);
    if (!line.text.empty() && line.text.back() == '\r') line.text.pop_back();
    // Decode: columns count characters. One error per line: the first bad
    // byte, else the first control character.
    line.col.assign(line.text.size() + 1, 0);
    bool line_ok = true;
    int col = 1;
    for (std::size_t i = 0; i < line.text.size() && line_ok;) {
      const std::size_t len = utf8SequenceLength(line.text, i);
      const auto c = static_cast<unsigned char>(line.text[i]);
      if (len == 0) {
        r.error(number, col, "invalid UTF-8 byte " + hexByte(c) + "; save the file as UTF-8");
        line_ok = false;
      }
      for (std::size_t k = 0; k < len; ++k) line.col[i + k] = col;
      i += len;
      ++col;
    }
    line.col.back() = col;
    for (std::size_t i = 0; i < line.text.size() && line_ok; ++i) {
      const auto c = static_cast<unsigned char>(line.text[i]);
      if ((c < 0x20 && c != '\t') || c == 0x7F) {
        r.error(number, line.col[i], "control character " + codePoint(c) + " is not allowed");
        line_ok = false;
      }
    }
    ok = ok && line_ok;
    if (line_ok) lines.push_back(std::move(line));
    if (last) break;
    start = end + 1;
  }
  if (!ok) return std::nullopt;
  return lines;
}

bool isContent(const Line& line) {
  const std::size_t i = line.text.find_first_not_of(" \t");
  return i != std::string::npos && line.text[i] != '#';
}

// ----- Tokens -------------------------------------------------------------------------

struct Token {
  std::string text;
  int line = 0;
  int col = 0;
};

/// Items of one line: separated by blanks, or by a comma with optional blanks.
class Scanner {
 public:
  Scanner(const Line& line, Reporter& r) : line_(line), text_(line.text), r_(r) {}

  std::optional<Token> item() {
    skipBlanks();
    if (i_ >= text_.size()) return std::nullopt;
    if (text_[i_] == ',') {
      r_.error(line_.number, line_.colAt(i_), "unexpected `,`: a value is missing before it");
      i_ = text_.size();
      failed_ = true;
      return std::nullopt;
    }
    const std::size_t start = i_;
    while (i_ < text_.size() && !isBlank(text_[i_]) && text_[i_] != ',') ++i_;
    Token token{text_.substr(start, i_ - start), line_.number, line_.colAt(start)};
    skipBlanks();
    if (i_ < text_.size() && text_[i_] == ',') {
      const std::size_t comma = i_++;
      skipBlanks();
      if (i_ >= text_.size()) {
        r_.error(line_.number, line_.colAt(comma), "unexpected `,` at the end of the line");
        failed_ = true;
      }
    }
    return token;
  }

  /// The rest of the line without trailing blanks, nullopt if empty.
  std::optional<Token> rest() {
    skipBlanks();
    std::size_t end = text_.size();
    while (end > i_ && isBlank(text_[end - 1])) --end;
    const std::size_t start = i_;
    i_ = text_.size();
    if (end == start) return std::nullopt;
    return Token{text_.substr(start, end - start), line_.number, line_.colAt(start)};
  }

  /// Column one blank after the last character: where a missing value belongs.
  int missingCol() const {
    std::size_t end = text_.size();
    while (end > 0 && isBlank(text_[end - 1])) --end;
    return line_.colAt(end) + 1;
  }

  bool failed() const { return failed_; }

 private:
  void skipBlanks() {
    while (i_ < text_.size() && isBlank(text_[i_])) ++i_;
  }

  const Line& line_;
  const std::string& text_;
  Reporter& r_;
  std::size_t i_ = 0;
  bool failed_ = false;
};

std::string numberText(double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, ptr) : std::string("?");
}

}  // namespace

// ----- The knowledge base parser ------------------------------------------------------

/// Builds an EnvironmentKnowledgeBase from lines, reporting every problem.
class KbParser {
 public:
  KbParser(const std::string& path, Reporter& r) : r_(r) { kb_.path_ = path; }

  std::optional<EnvironmentKnowledgeBase> parse(const std::vector<Line>& lines) {
    if (std::none_of(lines.begin(), lines.end(), isContent)) {
      r_.error(1, 1,
               "the knowledge base is empty: it has no locations and no `tourSpecification` "
               "(format: key, location id, values; one entry a line)");
      return std::nullopt;
    }
    const Line* previous = nullptr;
    for (const Line& line : lines) {
      if (!isContent(line)) continue;
      entry(line, previous);
      previous = &line;
    }
    if (!r_.empty()) return std::nullopt;
    complete();
    if (!r_.empty()) return std::nullopt;
    for (auto& [id, partial] : partial_) kb_.locations_.push_back(std::move(partial.location));
    return std::move(kb_);
  }

 private:
  struct Partial {
    KbLocation location;
    int col = 0;                                   // column of the key of the location's first entry
    std::array<int, kLocationKeyCount> line_of{};  // line of each key's entry, 0 if absent
  };

  void error(const Token& at, const std::string& message) { r_.error(at.line, at.col, message); }

  void entry(const Line& line, const Line* previous) {
    Scanner sc(line, r_);
    std::optional<Token> key = sc.item();
    if (!key) return;
    const int k = keyIndex(key->text);
    if (k < 0) {
      error(*key, unknownKey(key->text, previous));
      return;
    }
    const KeyInfo& info = kKeys[static_cast<std::size_t>(k)];
    std::vector<Token> values;
    if (info.kind == Kind::kText) {
      if (auto id = sc.item()) {
        values.push_back(std::move(*id));
        if (auto text = sc.rest()) values.push_back(std::move(*text));
      }
    } else {
      while (auto token = sc.item()) values.push_back(std::move(*token));
    }
    const int missing_col = sc.missingCol();
    auto missing = [&](const std::string& message) {
      if (!sc.failed()) r_.error(line.number, missing_col, message);
    };
    auto too_many = [&](const Token& at, const std::string& message) {
      if (!sc.failed()) error(at, message);
    };
    if (values.empty()) {
      missing(backticked(info.name) + " needs " + describeValues(info));
      return;
    }
    if (info.kind == Kind::kTour) {
      tour(*key, values, missing, too_many);
      return;
    }
    const std::optional<std::int32_t> id = parseLocationId(values[0].text);
    if (!id) {
      error(values[0], "expected a location id (a whole number from 1 to " + std::to_string(kMaxLocationId) +
                           "), found " + backticked(values[0].text));
    }
    bool complete_entry = true;  // no count problem (a duplicate is then worth reporting)
    KbLocation scratch;
    KbLocation& loc = id ? partial_[*id].location : scratch;
    switch (info.kind) {
      case Kind::kText: {
        if (values.size() < 2) {
          missing(backticked(info.name) + " of location " + values[0].text + " has no text");
          complete_entry = false;
          break;
        }
        const Token& text = values[1];
        if (text.text.size() > kMaxTextBytes) {
          error(text, backticked(info.name) + " of location " + values[0].text + " is " +
                          std::to_string(text.text.size()) + " bytes long; the runtime holds at most " +
                          std::to_string(kMaxTextBytes) + " bytes (UTF-8)");
        }
        textSlot(loc, static_cast<std::size_t>(k)) = text.text;
        break;
      }
      case Kind::kPoint: {
        Eigen::Vector3d v = Eigen::Vector3d::Zero();
        for (std::size_t i = 1; i < values.size() && i <= 3; ++i)
          v[static_cast<Eigen::Index>(i - 1)] = number(info, values[i]);
        if (values.size() < 4) {
          const std::size_t found = values.size() - 1;
          missing(backticked(info.name) + " takes " + describeValues(info) + "; found " + std::to_string(found) +
                  " number" + (found == 1 ? "" : "s"));
          complete_entry = false;
        } else if (values.size() > 4) {
          too_many(values[4], "too many values: " + backticked(info.name) + " takes " + describeValues(info));
          complete_entry = false;
        }
        (k == 1 ? loc.pose : loc.gesture_target) = v;
        break;
      }
      case Kind::kCultural: {
        loc.cultural_knowledge.clear();
        for (std::size_t i = 1; i < values.size() && i <= kMaxCulturalKeys; ++i) {
          const std::string& key_text = values[i].text;
          if (!isCulturalKey(key_text)) {
            error(values[i], backticked(key_text) +
                                 " is not a cultural knowledge key (an ASCII letter, then letters, digits or `_`)");
          } else if (key_text.size() > kMaxCulturalKeyBytes) {
            error(values[i], "cultural knowledge key `" + key_text.substr(0, 20) + "...` is " +
                                 std::to_string(key_text.size()) + " bytes long; at most " +
                                 std::to_string(kMaxCulturalKeyBytes) + " are allowed");
          }
          loc.cultural_knowledge.push_back(key_text);
        }
        if (values.size() < 2) {
          missing("`culturalKnowledge` of location " + values[0].text + " lists no keys");
          complete_entry = false;
        } else if (values.size() > kMaxCulturalKeys + 1) {
          too_many(values[kMaxCulturalKeys + 1],
                   "more than " + std::to_string(kMaxCulturalKeys) + " cultural knowledge keys for one location");
          complete_entry = false;
        }
        break;
      }
      case Kind::kTour: break;
    }
    if (!id) return;
    Partial& p = partial_[*id];
    if (p.location.line == 0) {
      p.location.id = *id;
      p.location.line = key->line;
      p.col = key->col;
    }
    int& seen = p.line_of[static_cast<std::size_t>(k)];
    if (seen != 0) {
      if (complete_entry) {  // as the schema: an entry with a count error is not also a duplicate
        error(*key, "duplicate " + backticked(info.name) + " entry for location " + std::to_string(*id) +
                        "; the first is on line " + std::to_string(seen));
      }
    } else {
      seen = key->line;
    }
  }

  template <typename Missing, typename TooMany>
  void tour(const Token& key, const std::vector<Token>& values, Missing& missing, TooMany& too_many) {
    if (tour_line_ != 0) {
      error(key, "duplicate `tourSpecification`; the first is on line " + std::to_string(tour_line_));
      return;
    }
    tour_line_ = key.line;
    const Token& count = values[0];
    const std::optional<std::uint64_t> n = parseCount(count.text);
    if (!n) {
      error(count, "expected the number of tour locations (a whole number), found " + backticked(count.text));
    } else if (*n > kMaxTourLocations) {
      error(count,
            "the tour has " + count.text + " locations; at most " + std::to_string(kMaxTourLocations) + " are allowed");
    }
    const std::size_t ids = values.size() - 1;
    for (std::size_t i = 1; i < values.size() && i <= kMaxTourLocations; ++i) {
      const std::optional<std::int32_t> id = parseLocationId(values[i].text);
      if (!id) {
        error(values[i], "expected a location id (a whole number from 1 to " + std::to_string(kMaxLocationId) +
                             "), found " + backticked(values[i].text));
        continue;
      }
      kb_.tour_.push_back(*id);
      tour_tokens_.push_back(values[i]);
    }
    if (ids == 0) {
      missing(std::string("`tourSpecification` lists no location ids after the count"));
    } else if (ids > kMaxTourLocations) {
      too_many(values[kMaxTourLocations + 1],
               "the tour lists more than " + std::to_string(kMaxTourLocations) + " locations");
    } else if (n && *n <= kMaxTourLocations && *n != ids) {
      std::string list;
      for (std::size_t i = 1; i < values.size(); ++i) list += (i > 1 ? " " : "") + values[i].text;
      error(count, "the tour count is " + count.text + " but " + std::to_string(ids) + " location id" +
                       (ids == 1 ? "" : "s") + " follow (" + list + ")");
    }
  }

  /// Checks across entries, once every line is well formed.
  void complete() {
    for (const auto& [id, p] : partial_) {
      for (std::size_t k = 0; k < kLocationKeyCount; ++k) {
        if (p.line_of[k] == 0) {
          r_.error(p.location.line, p.col,
                   "location " + std::to_string(id) + " has no " + backticked(kKeys[k].name) + " entry");
        }
      }
    }
    if (tour_line_ == 0) {
      r_.error(1, 1,
               "the knowledge base has no `tourSpecification` (the number of locations, then their ids in "
               "visiting order)");
      return;
    }
    std::string known;
    int listed = 0;
    for (const auto& entry : partial_) {
      if (listed++ == 12) break;
      known += (known.empty() ? "" : ", ") + std::to_string(entry.first);
    }
    for (std::size_t i = 0; i < kb_.tour_.size(); ++i) {
      if (partial_.count(kb_.tour_[i]) == 0) {
        error(tour_tokens_[i],
              "the tour visits location " + std::to_string(kb_.tour_[i]) +
                  ", which the knowledge base does not define (locations: " + (known.empty() ? "none" : known) + ")");
      }
    }
  }

  double number(const KeyInfo& info, const Token& token) {
    const std::string& s = token.text;
    if (!isDecimal(s)) {
      const std::string why =
          looksLikeOtherFloat(s) ? " (write a plain decimal such as 0.82: no exponent, INF or NaN)" : "";
      error(token, "expected a number in " + backticked(info.name) + " (" + str(info.coordinates) + "), found " +
                       backticked(s) + why);
      return 0.0;
    }
    const char* first = s.data() + (s[0] == '+' ? 1 : 0);
    double v = 0.0;
    auto [ptr, ec] = std::from_chars(first, s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || v > kMaxAbsCoordinate || v < -kMaxAbsCoordinate) {
      error(token, backticked(s) + " is out of range: coordinates are at most " +
                       std::to_string(static_cast<long long>(kMaxAbsCoordinate)) + " in magnitude");
      return 0.0;
    }
    return v;
  }

  static std::string& textSlot(KbLocation& loc, std::size_t key) {
    switch (key) {
      case 0: return loc.description;
      case 3:
      case 4:
      case 5: return loc.pre_gesture_message[key - 3];
      default: return loc.post_gesture_message[key - 6];
    }
  }

  static std::string unknownKey(const std::string& word, const Line* previous) {
    if (word == "robotLocation") {
      return "unknown key `robotLocation`: it was renamed in version 1.2 of D5.4.2; write `robotLocationPose`";
    }
    for (const KeyInfo& k : kKeys) {
      if (lower(k.name) == lower(word)) {
        return "unknown key " + backticked(word) + " (did you mean " + backticked(k.name) +
               "? keys are case-sensitive)";
      }
    }
    if (previous != nullptr) {
      const std::size_t s = previous->text.find_first_not_of(" \t");
      const std::size_t e = previous->text.find_first_of(" \t,", s);
      const int k = keyIndex(std::string_view(previous->text).substr(s, e == std::string::npos ? e : e - s));
      if (k >= 0 && kKeys[static_cast<std::size_t>(k)].kind == Kind::kText) {
        return "unknown key " + backticked(word) + "; if this line continues the text on line " +
               std::to_string(previous->number) + ", join them: an entry is one line";
      }
    }
    return "unknown key " + backticked(word) + ": a line starts with a key such as `robotLocationDescription`";
  }

  Reporter& r_;
  EnvironmentKnowledgeBase kb_;
  std::map<std::int32_t, Partial> partial_;
  int tour_line_ = 0;
  std::vector<Token> tour_tokens_;  // parallel to kb_.tour_
};

// ----- Public API ----------------------------------------------------------------------

KbResult<EnvironmentKnowledgeBase> EnvironmentKnowledgeBase::load(const std::string& dat_path) {
  Reporter r(dat_path);
  std::optional<std::vector<Line>> lines = readLines(dat_path, "knowledge base", r);
  if (!lines) return KbResult<EnvironmentKnowledgeBase>::failure(r.take());
  KbParser parser(dat_path, r);
  std::optional<EnvironmentKnowledgeBase> kb = parser.parse(*lines);
  if (!kb) return KbResult<EnvironmentKnowledgeBase>::failure(r.take());
  return KbResult<EnvironmentKnowledgeBase>::success(std::move(*kb));
}

KbResult<KbConfiguration> EnvironmentKnowledgeBase::loadConfiguration(const std::string& ini_path) {
  Reporter r(ini_path);
  std::optional<std::vector<Line>> lines = readLines(ini_path, "configuration", r);
  if (!lines) return KbResult<KbConfiguration>::failure(r.take());
  std::map<std::string, Token> values;
  bool kb_written = false;
  for (const Line& line : *lines) {
    if (!isContent(line)) continue;
    const std::string& t = line.text;
    const std::size_t ks = t.find_first_not_of(" \t");
    std::size_t ke = t.find_first_of(" \t", ks);
    if (ke == std::string::npos) ke = t.size();
    std::size_t vs = t.find_first_not_of(" \t", ke);
    if (vs == std::string::npos) vs = t.size();
    std::size_t ve = t.size();
    while (ve > vs && isBlank(t[ve - 1])) --ve;
    const Token key{t.substr(ks, ke - ks), line.number, line.colAt(ks)};
    const Token value{t.substr(vs, ve - vs), line.number, line.colAt(vs)};
    const std::string name = key.text.substr(0, key.text.find('='));
    kb_written = kb_written || name == "knowledgeBase";
    if (key.text.find('=') != std::string::npos || (!value.text.empty() && value.text[0] == '=')) {
      r.error(key.line, key.col,
              "write `" + (name.empty() ? std::string("key") : name) + " value` separated by blanks, without `=`");
      continue;
    }
    if (key.text != "knowledgeBase" && key.text != "verboseMode") {
      std::string hint;
      for (const char* known : {"knowledgeBase", "verboseMode"}) {
        if (lower(known) == lower(key.text)) hint = std::string(" (did you mean `") + known + "`?)";
      }
      r.error(key.line, key.col, "unknown configuration key " + backticked(key.text) + hint);
      continue;
    }
    if (values.count(key.text) != 0) {
      r.error(key.line, key.col,
              "duplicate " + backticked(key.text) + "; the first is on line " + std::to_string(values[key.text].line));
      continue;
    }
    if (value.text.empty()) {
      r.error(key.line, key.col + static_cast<int>(key.text.size()), backticked(key.text) + " needs a value");
      continue;
    }
    values[key.text] = value;
  }
  KbConfiguration config;
  if (auto v = values.find("verboseMode"); v != values.end()) {
    if (v->second.text != "true" && v->second.text != "false") {
      r.error(v->second.line, v->second.col,
              "`verboseMode` must be `true` or `false`, found " + backticked(v->second.text));
    }
    config.verbose_mode = v->second.text == "true";
  }
  auto kb = values.find("knowledgeBase");
  if (kb == values.end()) {
    if (!kb_written) r.error(1, 1, "the configuration has no `knowledgeBase` (the file name of the knowledge base)");
    return KbResult<KbConfiguration>::failure(r.take());
  }
  config.knowledge_base = kb->second.text;
  config.knowledge_base_path = (fs::path(ini_path).parent_path() / kb->second.text).string();
  std::error_code ec;
  if (!fs::is_regular_file(config.knowledge_base_path, ec)) {
    // (a directory or FIFO exists: "not found" sent the user looking for a typo)
    const char* why = fs::is_directory(config.knowledge_base_path, ec) ? " is a directory, not a knowledge base file"
                      : fs::exists(config.knowledge_base_path, ec)     ? " is not a regular file"
                                                                       : " not found";
    r.error(kb->second.line, kb->second.col,
            "knowledge base file " + backticked(config.knowledge_base) + why + " (looked for " +
                backticked(config.knowledge_base_path) + "; the name is relative to the configuration file's folder)");
  }
  if (!r.empty()) return KbResult<KbConfiguration>::failure(r.take());
  return KbResult<KbConfiguration>::success(std::move(config));
}

KbResult<EnvironmentKnowledgeBase> EnvironmentKnowledgeBase::loadFromConfiguration(const std::string& ini_path,
                                                                                   std::ostream& verbose_out) {
  KbResult<KbConfiguration> config = loadConfiguration(ini_path);
  if (!config) return KbResult<EnvironmentKnowledgeBase>::failure(config.errors());
  KbResult<EnvironmentKnowledgeBase> kb = load(config.value().knowledge_base_path);
  if (kb && config.value().verbose_mode) kb.value().print(verbose_out);
  return kb;
}

const KbLocation* EnvironmentKnowledgeBase::find(std::int32_t id) const noexcept {
  auto it = std::lower_bound(locations_.begin(), locations_.end(), id,
                             [](const KbLocation& loc, std::int32_t key) { return loc.id < key; });
  return it != locations_.end() && it->id == id ? &*it : nullptr;
}

const KbLocation* EnvironmentKnowledgeBase::tourLocation(std::size_t index) const noexcept {
  return index < tour_.size() ? find(tour_[index]) : nullptr;
}

void EnvironmentKnowledgeBase::print(std::ostream& out) const {
  static constexpr std::array<const char*, kLanguageCount> kLanguageNames = {"English", "isiZulu", "Kinyarwanda"};
  auto point = [](const Eigen::Vector3d& v) {
    return "(" + numberText(v.x()) + ", " + numberText(v.y()) + ", " + numberText(v.z()) + ")";
  };
  auto row = [&out](const std::string& label, const std::string& value) {
    out << "  " << label << std::string(label.size() < 34 ? 34 - label.size() : 1, ' ') << value << '\n';
  };
  out << "Environment knowledge base " << path_ << ": " << locations_.size() << " location"
      << (locations_.size() == 1 ? "" : "s") << '\n';
  for (const KbLocation& loc : locations_) {
    out << "Location " << loc.id << '\n';
    row("Description", loc.description);
    row("Robot location pose (x y theta)", point(loc.pose));
    row("Gesture target (x y z)", point(loc.gesture_target));
    for (std::size_t l = 0; l < kLanguageCount; ++l) {
      row(std::string("Pre-gesture message ") + kLanguageNames[l], loc.pre_gesture_message[l]);
    }
    for (std::size_t l = 0; l < kLanguageCount; ++l) {
      row(std::string("Post-gesture message ") + kLanguageNames[l], loc.post_gesture_message[l]);
    }
    std::string keys;
    for (const std::string& k : loc.cultural_knowledge) keys += (keys.empty() ? "" : " ") + k;
    row("Cultural knowledge", keys);
  }
  out << "Tour (" << tour_.size() << " location" << (tour_.size() == 1 ? "" : "s") << "):";
  for (std::int32_t id : tour_) out << ' ' << id;
  out << '\n';
}

}  // namespace btgen
