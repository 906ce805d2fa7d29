// Unit tests of the simulated robot's parts that do not need the generated
// mission: the exhibit list, the tour plan, the phrase table and languages,
// the command line. The end-to-end runs are tests/check_robot.py.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "options.hpp"
#include "speech.hpp"
#include "tour_plan.hpp"

namespace lab_tour_robot {
namespace {

const std::string kRepo = BTGEN_REPO_DIR;

const btgen::EnvironmentKnowledgeBase& shipped_kb() {
  static const btgen::EnvironmentKnowledgeBase kb = [] {
    auto r = btgen::EnvironmentKnowledgeBase::load(kRepo + "/data/environmentKnowledgeBaseInput.dat");
    if (!r) {
      ADD_FAILURE() << r.errorText();
      std::abort();
    }
    return std::move(r).value();
  }();
  return kb;
}

TEST(ExhibitList, TakesIdsInOrder) {
  std::int32_t id = 0;
  std::string_view rest;
  ASSERT_EQ(take_first_exhibit("4;3;2", id, rest), ListRead::kTaken);
  EXPECT_EQ(id, 4);
  EXPECT_EQ(rest, "3;2");
  ASSERT_EQ(take_first_exhibit(rest, id, rest), ListRead::kTaken);
  EXPECT_EQ(id, 3);
  ASSERT_EQ(take_first_exhibit(rest, id, rest), ListRead::kTaken);
  EXPECT_EQ(id, 2);
  EXPECT_EQ(rest, "");
  EXPECT_EQ(take_first_exhibit(rest, id, rest), ListRead::kEmpty);
}

TEST(ExhibitList, BlanksAndMistakes) {
  std::int32_t id = 0;
  std::string_view rest;
  EXPECT_EQ(take_first_exhibit("  ", id, rest), ListRead::kEmpty);
  ASSERT_EQ(take_first_exhibit(" 12 ; 7", id, rest), ListRead::kTaken);
  EXPECT_EQ(id, 12);
  for (std::string_view bad : {"x", ";4", "04", "-1", "0", "2147483648", "4 5", "1.5"}) {
    EXPECT_EQ(take_first_exhibit(bad, id, rest), ListRead::kMalformed) << bad;
  }
  ASSERT_EQ(take_first_exhibit("2147483647", id, rest), ListRead::kTaken);
  EXPECT_EQ(id, 2147483647);
  EXPECT_EQ(exhibit_list_text({4, 3, 2}), "4;3;2");
  EXPECT_EQ(exhibit_list_text({}), "");
}

TEST(TourPlan, ShippedBaseStartsAndEndsAtPeppersStartingLocation) {
  const TourPlan plan = plan_tour(shipped_kb());
  EXPECT_EQ(plan.home, 1);
  EXPECT_EQ(plan.exit, 5);
  EXPECT_EQ(plan.exhibits, (std::vector<std::int32_t>{4, 3, 2}));
}

TEST(Speech, Placeholders) {
  for (std::string_view p : {"No message in isiZulu", "no translation yet", "TODO: translate", "TBD", "xxx", "...",
                             "Placeholder text", "Lorem ipsum dolor"}) {
    EXPECT_TRUE(is_placeholder(p)) << p;
  }
  for (std::string_view m : {"Iyi yitwa rumba", "Nothing to say", "See you again soon", "xx", "Notice"}) {
    EXPECT_FALSE(is_placeholder(m)) << m;
  }
}

TEST(Speech, FallsBackToEnglishWithAMarker) {
  const std::array<std::string_view, 3> texts = {"Hello", "No message in isiZulu", "Muraho"};
  EXPECT_EQ(resolve_text(texts, btgen::Language::kEnglish).text, "Hello");
  EXPECT_FALSE(resolve_text(texts, btgen::Language::kEnglish).fallback);
  EXPECT_EQ(resolve_text(texts, btgen::Language::kKinyarwanda).text, "Muraho");
  const Utterance zulu = resolve_text(texts, btgen::Language::kIsiZulu);
  EXPECT_EQ(zulu.text, "[no isiZulu translation] Hello");
  EXPECT_TRUE(zulu.fallback);
  EXPECT_EQ(resolve_text({"Hi", "", ""}, btgen::Language::kKinyarwanda).text, "[no Kinyarwanda translation] Hi");
  EXPECT_EQ(resolve_text({"TODO", "", ""}, btgen::Language::kEnglish).text, "[no message]");
}

TEST(Speech, LanguageNames) {
  btgen::Language l{};
  ASSERT_TRUE(parse_language("isiZulu", l));
  EXPECT_EQ(l, btgen::Language::kIsiZulu);
  ASSERT_TRUE(parse_language("KINYARWANDA", l));
  EXPECT_EQ(l, btgen::Language::kKinyarwanda);
  EXPECT_FALSE(parse_language("Zulu", l));
  EXPECT_EQ(language_name(btgen::Language::kEnglish), "English");
}

TEST(Speech, BookUsesTheKnowledgeBase) {
  const TourPlan plan = plan_tour(shipped_kb());
  const SpeechBook rw = SpeechBook::build(shipped_kb(), btgen::Language::kKinyarwanda, plan.home, plan.exit);
  ASSERT_NE(rw.location_message(4, false), nullptr);
  EXPECT_EQ(rw.location_message(4, false)->text, "Iyi yitwa rumba");
  EXPECT_EQ(rw.location_message(4, true)->text, "Tuyikoresha mukwigisha mobile robotikisi");
  EXPECT_EQ(rw.location_message(99, true), nullptr);
  const std::vector<Utterance>* welcome = rw.phrase("welcome");
  ASSERT_NE(welcome, nullptr);
  ASSERT_EQ(welcome->size(), 2u);
  EXPECT_EQ((*welcome)[0].text, shipped_kb().find(1)->preGestureMessage(btgen::Language::kKinyarwanda));
  EXPECT_EQ(rw.phrase("goodbye")->at(0).text, "Tuzongere kubonana ubutaha");
  EXPECT_EQ(rw.phrase("follow_me")->at(0).text, "[no Kinyarwanda translation] Please follow me.");
  EXPECT_EQ(rw.phrase("no_such_phrase"), nullptr);

  const SpeechBook zu = SpeechBook::build(shipped_kb(), btgen::Language::kIsiZulu, plan.home, plan.exit);
  EXPECT_EQ(zu.location_message(2, false)->text, "[no isiZulu translation] This is the Pepper humanoid robot");
  // 10 placeholder messages in the base, and the 6 phrases written in the table.
  EXPECT_EQ(zu.fallback_count(), 16u);
  const SpeechBook en = SpeechBook::build(shipped_kb(), btgen::Language::kEnglish, plan.home, plan.exit);
  EXPECT_EQ(en.fallback_count(), 0u);
  EXPECT_EQ(en.phrase("end_of_tour")->at(0).text, "I hope you enjoyed the tour");
}

// Every `message` default of the mission's TreeNodesModel has a phrase.
TEST(Speech, PhraseTableCoversTheMission) {
  std::ifstream in(kRepo + "/missions/LabTour.xml");
  ASSERT_TRUE(in) << "missions/LabTour.xml";
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  const std::regex port(R"re(<input_port name="message"[^>]*default="([^"]*)")re");
  std::set<std::string> keys;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), port); it != std::sregex_iterator(); ++it) {
    keys.insert((*it)[1].str());
  }
  EXPECT_EQ(keys.size(), 9u);
  std::set<std::string> table;
  for (const Phrase& p : phrase_table()) table.insert(std::string(p.key));
  for (const std::string& k : keys) EXPECT_TRUE(table.count(k)) << "no phrase for `" << k << "`";
}

Options parse(std::initializer_list<const char*> args, bool expect_ok = true, std::string* error_out = nullptr) {
  std::vector<const char*> argv{"lab_tour_robot"};
  argv.insert(argv.end(), args.begin(), args.end());
  Options o;
  std::string error;
  const bool ok = parse_options(static_cast<int>(argv.size()), argv.data(), o, error);
  EXPECT_EQ(ok, expect_ok) << error;
  if (error_out != nullptr) *error_out = error;
  return o;
}

TEST(Options, Defaults) {
  const Options o = parse({});
  EXPECT_EQ(o.language, btgen::Language::kEnglish);
  EXPECT_EQ(o.kb_config, "data/environmentKnowledgeBaseConfiguration.ini");
  EXPECT_FALSE(o.kb_config_given);
  EXPECT_TRUE(o.answer_yes);
  EXPECT_FALSE(o.answer_given);
  EXPECT_FALSE(o.trace);
  EXPECT_EQ(o.tick_ms, 0);
  EXPECT_EQ(o.max_ticks, kDefaultMaxTicks);
}

TEST(Options, Values) {
  const Options o = parse({"--language", "isiZulu", "--answer=no", "--trace", "--tick-ms", "250", "--max-ticks=40",
                           "--kb-config", "x.ini", "--scenario", "s.scenario"});
  EXPECT_EQ(o.language, btgen::Language::kIsiZulu);
  EXPECT_FALSE(o.answer_yes);
  EXPECT_TRUE(o.answer_given);
  EXPECT_TRUE(o.trace);
  EXPECT_EQ(o.tick_ms, 250);
  EXPECT_EQ(o.max_ticks, 40);
  EXPECT_TRUE(o.max_ticks_given);
  EXPECT_EQ(o.kb_config, "x.ini");
  EXPECT_EQ(o.scenario, "s.scenario");
  EXPECT_TRUE(parse({"--help"}).help);
}

TEST(Options, Mistakes) {
  std::string e;
  parse({"--language", "French"}, false, &e);
  EXPECT_EQ(e, "unknown language `French`: use English, isiZulu or Kinyarwanda");
  parse({"--answer", "maybe"}, false, &e);
  EXPECT_EQ(e, "`--answer` is yes or no, not `maybe`");
  parse({"--tick-ms", "-5"}, false, &e);
  EXPECT_EQ(e, "`--tick-ms` is a whole number of milliseconds from 0 to 60000, not `-5`");
  parse({"--max-ticks", "0"}, false, &e);
  EXPECT_EQ(e, "`--max-ticks` is a whole number from 1 to 1000000000, not `0`");
  parse({"--max-ticks"}, false, &e);
  EXPECT_EQ(e, "`--max-ticks` needs a value");
  parse({"--speed", "3"}, false, &e);
  EXPECT_EQ(e, "unknown option `--speed`");
  parse({"--trace=yes"}, false, &e);
  EXPECT_EQ(e, "`--trace` takes no value");
  parse({"--answer", "yes", "--answer", "no"}, false, &e);
  EXPECT_EQ(e, "`--answer` is given twice");
  parse({"tour"}, false, &e);
  EXPECT_EQ(e, "unexpected argument `tour` (options start with --)");
}

}  // namespace
}  // namespace lab_tour_robot
