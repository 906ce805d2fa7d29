// What the simulated Pepper says, in the visitor's language.
//
// Two sources of text:
//  - the knowledge base: the pre- and post-gesture messages of every
//    location, in English, isiZulu and Kinyarwanda (data/README.md);
//  - the phrase table (phrases.cpp): what the speech nodes without a location
//    say, named by their `message` port (`welcome`, `follow_me`, ...).
//
// A text that is missing in the chosen language, or that is a placeholder
// such as the shipped base's "No message in isiZulu", is never said as it
// is: the robot says the English text after a visible marker,
// "[no isiZulu translation] ...". Nothing is machine-translated or guessed.
//
// Everything is resolved once, at start-up (SpeechBook::build); looking a
// text up during a tick does not allocate.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "btgen/environment_knowledge_base.hpp"

namespace lab_tour_robot {

/// "English", "isiZulu", "Kinyarwanda".
[[nodiscard]] std::string_view language_name(btgen::Language language) noexcept;

/// Reads a language name as the command line gives it (any letter case).
[[nodiscard]] bool parse_language(std::string_view text, btgen::Language& out) noexcept;

/// True for a message that stands in for a missing one. The same rule as
/// `btgen lint-kb` (generator/btgen/kb/lint.py, _PLACEHOLDER_RE): "No message in
/// isiZulu", "TODO ...", "TBD", "placeholder", "xxx", "...", ... (any case).
[[nodiscard]] bool is_placeholder(std::string_view text);

/// One text of the phrase table: the English text, and the isiZulu and
/// Kinyarwanda ones where a checked translation exists (else empty).
struct PhraseText {
  std::array<std::string_view, btgen::kLanguageCount> text;
};

/// Where a phrase takes its words from.
enum class PhraseSource : std::uint8_t {
  kTable,            ///< its PhraseText
  kHomeMessages,     ///< the pre- then post-gesture message of the tour's home location
  kExitPreMessage,   ///< the pre-gesture message of the tour's exit location
  kExitPostMessage,  ///< the post-gesture message of the tour's exit location
};

/// One row of the phrase table.
struct Phrase {
  std::string_view key;  ///< the value of a speech node's `message` port
  PhraseSource source;
  PhraseText table;  ///< used when source == kTable
};

/// The phrase table (phrases.cpp): every default `message` key of
/// missions/LabTour.xml's TreeNodesModel.
[[nodiscard]] const std::vector<Phrase>& phrase_table();

/// A text ready to be said: what the robot says, and whether it fell back
/// to English (or to nothing at all).
struct Utterance {
  std::string text;
  bool fallback = false;
};

/// Picks the text of `language` from the three, or falls back to English
/// with the "[no <language> translation] " marker; a missing or placeholder
/// English text gives "[no message]".
[[nodiscard]] Utterance resolve_text(const std::array<std::string_view, btgen::kLanguageCount>& texts,
                                     btgen::Language language);

/// Every text the robot can say during the mission, resolved for one language.
class SpeechBook {
 public:
  /// Resolves the knowledge base's messages and the phrase table. `home`
  /// and `exit` are the ids the tour starts and ends at (tour_plan.hpp).
  static SpeechBook build(const btgen::EnvironmentKnowledgeBase& kb, btgen::Language language, std::int32_t home,
                          std::int32_t exit);

  [[nodiscard]] btgen::Language language() const noexcept { return language_; }

  /// The utterances of a phrase key (one or two), or nullptr for an unknown key.
  [[nodiscard]] const std::vector<Utterance>* phrase(std::string_view key) const noexcept;

  /// The pre- or post-gesture message of a location, or nullptr for an unknown id.
  [[nodiscard]] const Utterance* location_message(std::int32_t id, bool post_gesture) const noexcept;

  /// How many texts (location messages and phrase-table rows) fell back to English.
  [[nodiscard]] std::size_t fallback_count() const noexcept { return fallbacks_; }

 private:
  struct LocationTexts {
    std::int32_t id;
    Utterance pre;
    Utterance post;
  };
  struct PhraseTexts {
    std::string key;
    std::vector<Utterance> utterances;
  };

  btgen::Language language_ = btgen::Language::kEnglish;
  std::vector<LocationTexts> locations_;  // sorted by id, as the base
  std::vector<PhraseTexts> phrases_;
  std::size_t fallbacks_ = 0;
};

}  // namespace lab_tour_robot
