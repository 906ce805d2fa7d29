// btgen::EnvironmentKnowledgeBase: reads the robot's environment knowledge
// base (CSSR4Africa D5.4.2 sections 4-6) and its configuration file.
//
// File formats: data/README.md. The reader accepts exactly the files that
// `btgen lint-kb` accepts without errors (tests/cpp/kb checks it on every
// file of tests/bad_kb); it does not print the linter's warnings.
//
// The document's three services:
//   printToScreen()  -> print(std::ostream&)
//   getValue(id, &v) -> find(id): a pointer to the location, or nullptr
//   getTour(&tour)   -> tour(): the ids in visiting order; its size() is the
//                       bound (the document's example reads one past the end)
//
// Errors are values, not exceptions: load*() return a KbResult holding either
// the result or every diagnostic, each formatted `path:line:col: error: message`
// like the Python linter. Robots often build with -fno-exceptions, and a
// malformed file is an expected event at start-up, not an exceptional one.
// Nothing here throws except std::bad_alloc from the standard containers
// (which terminates under -fno-exceptions). Loading allocates (std::string,
// std::vector): do it once at start-up, never in a tick.
//
// Limits (kb_limits.hpp) are enforced with errors, never by truncation.
#ifndef BTGEN_ENVIRONMENT_KNOWLEDGE_BASE_HPP
#define BTGEN_ENVIRONMENT_KNOWLEDGE_BASE_HPP

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "btgen/kb_limits.hpp"

namespace btgen {

/// Languages of the messages, in file order.
enum class Language : std::uint8_t { kEnglish = 0, kIsiZulu = 1, kKinyarwanda = 2 };
inline constexpr std::size_t kLanguageCount = 3;

/// One location: every value of the ten location keys of one id.
struct KbLocation {
  std::int32_t id = 0;
  int line = 0;  ///< first line of the location in the .dat file
  std::string description;
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();                ///< x [m], y [m], theta [deg]
  Eigen::Vector3d gesture_target = Eigen::Vector3d::Zero();      ///< x, y, z [m]
  std::array<std::string, kLanguageCount> pre_gesture_message;   ///< indexed by Language
  std::array<std::string, kLanguageCount> post_gesture_message;  ///< indexed by Language
  std::vector<std::string> cultural_knowledge;                   ///< keys of the culture knowledge base

  [[nodiscard]] const std::string& preGestureMessage(Language language) const noexcept {
    return pre_gesture_message[static_cast<std::size_t>(language)];
  }
  [[nodiscard]] const std::string& postGestureMessage(Language language) const noexcept {
    return post_gesture_message[static_cast<std::size_t>(language)];
  }
};

/// The configuration file (.ini).
struct KbConfiguration {
  std::string knowledge_base;       ///< as written in the file
  std::string knowledge_base_path;  ///< resolved against the folder of the .ini
  bool verbose_mode = false;
};

/// Either a value or the diagnostics explaining why there is none.
template <typename T>
class [[nodiscard]] KbResult {
 public:
  static KbResult success(T value) { return KbResult(std::move(value), {}); }
  static KbResult failure(std::vector<std::string> errors) { return KbResult(std::nullopt, std::move(errors)); }

  [[nodiscard]] bool ok() const noexcept { return value_.has_value(); }
  explicit operator bool() const noexcept { return ok(); }

  /// The value; calling this on a failure is a programming error and aborts.
  [[nodiscard]] const T& value() const& {
    if (!value_) std::abort();
    return *value_;
  }
  [[nodiscard]] T&& value() && {
    if (!value_) std::abort();
    return std::move(*value_);
  }

  /// Every diagnostic, `path:line:col: error: message`, sorted by position.
  [[nodiscard]] const std::vector<std::string>& errors() const noexcept { return errors_; }
  /// The diagnostics joined with newlines (empty on success).
  [[nodiscard]] std::string errorText() const {
    std::string text;
    for (const std::string& e : errors_) {
      if (!text.empty()) text += '\n';
      text += e;
    }
    return text;
  }

 private:
  KbResult(std::optional<T> value, std::vector<std::string> errors)
      : value_(std::move(value)), errors_(std::move(errors)) {}

  std::optional<T> value_;
  std::vector<std::string> errors_;
};

class EnvironmentKnowledgeBase {
 public:
  /// Read a configuration file (`knowledgeBase`, `verboseMode`).
  [[nodiscard]] static KbResult<KbConfiguration> loadConfiguration(const std::string& ini_path);

  /// Read a knowledge base file (.dat).
  [[nodiscard]] static KbResult<EnvironmentKnowledgeBase> load(const std::string& dat_path);

  /// The document's constructor: read the configuration, then the base it
  /// names; in verbose mode, print the base to `verbose_out`.
  [[nodiscard]] static KbResult<EnvironmentKnowledgeBase> loadFromConfiguration(const std::string& ini_path,
                                                                                std::ostream& verbose_out);

  /// The location with this id, or nullptr (the document's getValue()).
  [[nodiscard]] const KbLocation* find(std::int32_t id) const noexcept;

  /// Location ids in visiting order (the document's getTour()). Every id
  /// names a location; iterate up to size(), not one further.
  [[nodiscard]] const std::vector<std::int32_t>& tour() const noexcept { return tour_; }

  /// The index-th location of the tour, or nullptr past its end.
  [[nodiscard]] const KbLocation* tourLocation(std::size_t index) const noexcept;

  /// Every location, sorted by id.
  [[nodiscard]] const std::vector<KbLocation>& locations() const noexcept { return locations_; }

  /// The file the base was read from, as given to load().
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

  /// Write every location and the tour, one value a line (the document's printToScreen()).
  void print(std::ostream& out) const;

 private:
  EnvironmentKnowledgeBase() = default;
  friend class KbParser;

  std::string path_;
  std::vector<KbLocation> locations_;  // sorted by id
  std::vector<std::int32_t> tour_;
};

}  // namespace btgen

#endif  // BTGEN_ENVIRONMENT_KNOWLEDGE_BASE_HPP
