#include "speech.hpp"

#include <algorithm>
#include <cctype>
#include <regex>

namespace lab_tour_robot {

namespace {

constexpr std::array<std::string_view, btgen::kLanguageCount> kLanguageNames = {"English", "isiZulu", "Kinyarwanda"};

bool equal_ignoring_case(std::string_view a, std::string_view b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  }
  return true;
}

std::array<std::string_view, btgen::kLanguageCount> texts_of(const std::array<std::string, btgen::kLanguageCount>& m) {
  return {m[0], m[1], m[2]};
}

}  // namespace

std::string_view language_name(btgen::Language language) noexcept {
  return kLanguageNames[static_cast<std::size_t>(language)];
}

bool parse_language(std::string_view text, btgen::Language& out) noexcept {
  for (std::size_t i = 0; i < kLanguageNames.size(); ++i) {
    if (equal_ignoring_case(text, kLanguageNames[i])) {
      out = static_cast<btgen::Language>(i);
      return true;
    }
  }
  return false;
}

bool is_placeholder(std::string_view text) {
  // generator/btgen/kb/lint.py, _PLACEHOLDER_RE (a full match, any case).
  static const std::regex kPlaceholder(R"((no (message|translation|text)\b.*|(todo|tbd|fixme)\b.*|placeholder\b.*)"
                                       R"(|to be translated\b.*|x{3,}|\.\.\.|lorem ipsum\b.*))",
                                       std::regex::ECMAScript | std::regex::icase);
  return std::regex_match(text.begin(), text.end(), kPlaceholder);
}

Utterance resolve_text(const std::array<std::string_view, btgen::kLanguageCount>& texts, btgen::Language language) {
  const auto usable = [](std::string_view t) { return !t.empty() && !is_placeholder(t); };
  const std::string_view wanted = texts[static_cast<std::size_t>(language)];
  if (usable(wanted)) return Utterance{std::string(wanted), false};
  const std::string_view english = texts[static_cast<std::size_t>(btgen::Language::kEnglish)];
  if (!usable(english)) return Utterance{"[no message]", true};
  if (language == btgen::Language::kEnglish) return Utterance{std::string(english), false};
  return Utterance{"[no " + std::string(language_name(language)) + " translation] " + std::string(english), true};
}

SpeechBook SpeechBook::build(const btgen::EnvironmentKnowledgeBase& kb, btgen::Language language, std::int32_t home,
                             std::int32_t exit) {
  SpeechBook book;
  book.language_ = language;
  for (const btgen::KbLocation& loc : kb.locations()) {
    book.locations_.push_back(LocationTexts{loc.id, resolve_text(texts_of(loc.pre_gesture_message), language),
                                            resolve_text(texts_of(loc.post_gesture_message), language)});
    book.fallbacks_ +=
        (book.locations_.back().pre.fallback ? 1u : 0u) + (book.locations_.back().post.fallback ? 1u : 0u);
  }
  auto message = [&book](std::int32_t id, bool post) {
    const Utterance* u = book.location_message(id, post);
    return u != nullptr ? *u : Utterance{"[no message: location " + std::to_string(id) + " is not in the base]", true};
  };
  for (const Phrase& p : phrase_table()) {
    PhraseTexts texts{std::string(p.key), {}};
    switch (p.source) {
      case PhraseSource::kTable:
        texts.utterances.push_back(resolve_text(p.table.text, language));
        book.fallbacks_ += texts.utterances.back().fallback ? 1u : 0u;
        break;
      case PhraseSource::kHomeMessages:
        texts.utterances.push_back(message(home, false));
        texts.utterances.push_back(message(home, true));
        break;
      case PhraseSource::kExitPreMessage: texts.utterances.push_back(message(exit, false)); break;
      case PhraseSource::kExitPostMessage: texts.utterances.push_back(message(exit, true)); break;
    }
    book.phrases_.push_back(std::move(texts));
  }
  return book;
}

const std::vector<Utterance>* SpeechBook::phrase(std::string_view key) const noexcept {
  for (const PhraseTexts& p : phrases_) {
    if (p.key == key) return &p.utterances;
  }
  return nullptr;
}

const Utterance* SpeechBook::location_message(std::int32_t id, bool post_gesture) const noexcept {
  auto it = std::lower_bound(locations_.begin(), locations_.end(), id,
                             [](const LocationTexts& l, std::int32_t key) { return l.id < key; });
  if (it == locations_.end() || it->id != id) return nullptr;
  return post_gesture ? &it->post : &it->pre;
}

}  // namespace lab_tour_robot
