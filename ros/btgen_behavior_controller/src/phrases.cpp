// The phrase table (see phrases.hpp).
//
// Translations: the isiZulu and Kinyarwanda phrases below are short, common
// phrasings written for this package, not texts checked by a native speaker.
// Have them checked before the robot says them to visitors; each row is one
// phrase in English, isiZulu and Kinyarwanda.
#include "phrases.hpp"

#include <array>
#include <cctype>
#include <cstddef>

namespace btgen_behavior_controller {
namespace {

struct Phrase {
  const char* id;
  std::array<const char*, 3> text;  // by Language
};

// Ids as in the production mission: 1 press yes/no, 2 follow me, 3 maybe
// another time, 4 welcome, 5 query tour, 7 goodbye.
constexpr std::array<Phrase, 6> kPhrases = {{
    {"1",
     {"Please press Yes or No on my tablet.", "Sicela ucindezele u-Yebo noma u-Cha kuthebulethi yami.",
      "Mukande kuri Yego cyangwa Oya kuri tablet yanjye."}},
    {"2", {"Please follow me.", "Sicela ungilandele.", "Nimunkurikire."}},
    {"3",
     {"No problem. Maybe another time.", "Akunankinga. Mhlawumbe ngesinye isikhathi.", "Nta kibazo. Wenda ubutaha."}},
    {"4",
     {"Hello! Welcome to the robotics lab. I am Pepper, your guide.",
      "Sawubona! Wamukelekile elebhu yamarobhothi. NginguPepper, umhambisi wakho.",
      "Muraho! Murakaza neza muri laboratwari ya robotikisi. Nitwa Pepper, ndi umuyobozi wanyu."}},
    {"5",
     {"Would you like me to show you around the lab? Please say yes or no.",
      "Ungathanda ukuthi ngikukhombise ilebhu? Sicela uthi yebo noma cha.",
      "Mwifuza ko mbatembereza muri laboratwari? Muvuge yego cyangwa oya."}},
    {"7",
     {"Goodbye, and thank you for your visit.", "Hamba kahle, siyabonga ngokuvakasha.",
      "Murabeho, murakoze kudusura."}},
}};

// Yes and no, per language (the production node's English and Kinyarwanda words, and isiZulu's).
constexpr std::array<std::array<const char*, 8>, 3> kYesWords = {{
    {"yes", "great", "absolutely", "go", "happy", "good", "love", nullptr},
    {"yebo", nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr},
    {"yego", "ntakibazo", "nibyo", nullptr, nullptr, nullptr, nullptr, nullptr},
}};
constexpr std::array<std::array<const char*, 2>, 3> kNoWords = {{
    {"no", nullptr},
    {"cha", nullptr},
    {"oya", nullptr},
}};

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  }
  return true;
}

template <std::size_t N>
bool has_word(std::string_view text, const std::array<const char*, N>& words) {
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && !std::isalpha(static_cast<unsigned char>(text[i]))) ++i;
    std::size_t j = i;
    while (j < text.size() && std::isalpha(static_cast<unsigned char>(text[j]))) ++j;
    const std::string_view word = text.substr(i, j - i);
    for (const char* w : words) {
      if (w != nullptr && !word.empty() && equal_ignoring_case(word, w)) return true;
    }
    i = j;
  }
  return false;
}

}  // namespace

std::optional<Language> parse_language(std::string_view name) {
  if (equal_ignoring_case(name, "English")) return Language::kEnglish;
  if (equal_ignoring_case(name, "IsiZulu")) return Language::kIsiZulu;
  if (equal_ignoring_case(name, "Kinyarwanda")) return Language::kKinyarwanda;
  return std::nullopt;
}

const char* language_name(Language language) {
  switch (language) {
    case Language::kEnglish: return "English";
    case Language::kIsiZulu: return "IsiZulu";
    case Language::kKinyarwanda: return "Kinyarwanda";
  }
  return "English";
}

const char* utility_phrase(std::string_view id, Language language) {
  for (const Phrase& p : kPhrases) {
    if (id == p.id) return p.text[static_cast<std::size_t>(language)];
  }
  return nullptr;
}

std::string utility_phrase_ids() {
  std::string ids;
  for (const Phrase& p : kPhrases) ids += (ids.empty() ? "" : ", ") + std::string(p.id);
  return ids;
}

Answer classify_answer(std::string_view transcription, Language language) {
  const std::size_t l = static_cast<std::size_t>(language);
  if (has_word(transcription, kYesWords[l])) return Answer::kYes;
  if (has_word(transcription, kNoWords[l])) return Answer::kNo;
  return Answer::kNone;
}

}  // namespace btgen_behavior_controller
