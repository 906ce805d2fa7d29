// The utility phrases of SayText and the words of a spoken yes or no, in the
// three languages of the Lab Tour.
//
// The production node takes its utility phrases from the CSSR4Africa culture
// knowledge base; this node keeps a small table of its own (phrases.cpp),
// numbered as the production mission numbers them, so that <SayText name="4"/>
// is the welcome in both.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace btgen_behavior_controller {

enum class Language { kEnglish = 0, kIsiZulu = 1, kKinyarwanda = 2 };

/// "English", "IsiZulu", "Kinyarwanda" (as the production node names them; any case).
std::optional<Language> parse_language(std::string_view name);
/// The name sent to textToSpeech and speechEvent: "English", "IsiZulu", "Kinyarwanda".
const char* language_name(Language language);

/// Utility phrase `id` (SayText's name attribute) in `language`, or nullptr when the table has no such id.
const char* utility_phrase(std::string_view id, Language language);
/// Every id of the table, for messages: "1, 2, 3, 4, 5, 7".
std::string utility_phrase_ids();

enum class Answer { kNone, kYes, kNo };
/// A transcription classified as the production node does (affirmative words
/// first, then negative ones), but matching whole words, case-insensitively.
Answer classify_answer(std::string_view transcription, Language language);

}  // namespace btgen_behavior_controller
