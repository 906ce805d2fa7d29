// Tests of btgen::EnvironmentKnowledgeBase on the shipped base and the
// bad inputs of tests/bad_kb (whose .stderr files hold the Python linter's
// exact output: the C++ reader must agree with it).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "btgen/environment_knowledge_base.hpp"

namespace {

namespace fs = std::filesystem;
using btgen::EnvironmentKnowledgeBase;
using btgen::KbLocation;
using btgen::Language;

const std::string kSource = BTGEN_SOURCE_DIR;

std::string src(const std::string& relative) { return kSource + "/" + relative; }

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// Diagnostics with the source directory removed, as the Python tests print them.
std::vector<std::string> relative(const std::vector<std::string>& errors) {
  std::vector<std::string> out;
  for (std::string e : errors) {
    for (std::size_t at; (at = e.find(kSource + "/")) != std::string::npos;) e.erase(at, kSource.size() + 1);
    out.push_back(e);
  }
  return out;
}

/// The error lines of a bad_kb case's expected linter output.
std::vector<std::string> expectedErrors(const std::string& stem) {
  std::vector<std::string> errors;
  for (const std::string& line : splitLines(readText(src("tests/bad_kb/" + stem + ".stderr")))) {
    if (line.find(": error: ") != std::string::npos) errors.push_back(line);
  }
  return errors;
}

std::vector<std::string> loadErrors(const std::string& stem) {
  auto kb = EnvironmentKnowledgeBase::load(src("tests/bad_kb/" + stem + ".dat"));
  EXPECT_FALSE(kb.ok()) << stem;
  return relative(kb.errors());
}

/// A scratch file under the system's temporary directory.
class TempFile {
 public:
  TempFile(const std::string& name, const std::string& contents)
      : path_((fs::temp_directory_path() /
               ("btgen_kb_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" + name))
                  .string()) {
    std::ofstream(path_, std::ios::binary) << contents;
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string minimal() { return readText(src("tests/bad_kb/ok_minimal.dat")); }

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// ----- Services on the shipped base -----------------------------------------------

TEST(EnvironmentKnowledgeBase, LooksUpLocationsOfTheShippedBase) {
  auto kb = EnvironmentKnowledgeBase::load(src("data/environmentKnowledgeBaseInput.dat"));
  ASSERT_TRUE(kb.ok()) << kb.errorText();
  const EnvironmentKnowledgeBase& base = kb.value();
  ASSERT_EQ(base.locations().size(), 5u);

  const KbLocation* roomba = base.find(4);
  ASSERT_NE(roomba, nullptr);
  EXPECT_EQ(roomba->id, 4);
  EXPECT_EQ(roomba->line, 46);
  EXPECT_EQ(roomba->description, "Roomba");
  EXPECT_EQ(roomba->pose, Eigen::Vector3d(5.0, 3.9, 110.0));
  EXPECT_EQ(roomba->gesture_target, Eigen::Vector3d(6.8, 4.8, 0.82));
  EXPECT_EQ(roomba->preGestureMessage(Language::kEnglish), "This is the Roomba");
  EXPECT_EQ(roomba->preGestureMessage(Language::kIsiZulu), "No message in isiZulu");
  EXPECT_EQ(roomba->preGestureMessage(Language::kKinyarwanda), "Iyi yitwa rumba");
  EXPECT_EQ(roomba->postGestureMessage(Language::kEnglish), "We use it for teaching mobile robotics");
  EXPECT_EQ(roomba->postGestureMessage(Language::kKinyarwanda), "Tuyikoresha mukwigisha mobile robotikisi");
  EXPECT_EQ(roomba->cultural_knowledge, std::vector<std::string>{"DeicticShape"});

  const KbLocation* start = base.find(1);
  ASSERT_NE(start, nullptr);
  EXPECT_EQ(start->description, "Pepper's starting location");
  EXPECT_EQ(start->pose, Eigen::Vector3d(2.6, 8.1, -90.0));
  EXPECT_EQ(start->preGestureMessage(Language::kKinyarwanda),
            "Murakazaneza muri laboratwari ya robotikisi muri kaneji meloni iniverisite yafurika.");
  EXPECT_EQ(start->cultural_knowledge, (std::vector<std::string>{"SymbolicShapeRespect", "BowExtentRespect"}));

  EXPECT_EQ(base.find(0), nullptr);
  EXPECT_EQ(base.find(6), nullptr);
  EXPECT_EQ(base.find(-1), nullptr);
}

TEST(EnvironmentKnowledgeBase, TourHasExactBounds) {
  auto kb = EnvironmentKnowledgeBase::load(src("data/environmentKnowledgeBaseInput.dat"));
  ASSERT_TRUE(kb.ok()) << kb.errorText();
  const EnvironmentKnowledgeBase& base = kb.value();
  EXPECT_EQ(base.tour(), (std::vector<std::int32_t>{1, 4, 3, 2, 5}));
  std::vector<std::string> visited;
  for (std::size_t i = 0; i < base.tour().size(); ++i) {
    const KbLocation* stop = base.tourLocation(i);
    ASSERT_NE(stop, nullptr) << i;
    visited.push_back(stop->description);
  }
  EXPECT_EQ(visited, (std::vector<std::string>{"Pepper's starting location", "Roomba", "Lynxmotion",
                                               "The (other) Pepper robot", "Pepper's starting location"}));
  // The document's example reads index numberOfLocations too: here there is nothing there.
  EXPECT_EQ(base.tourLocation(base.tour().size()), nullptr);
  EXPECT_EQ(base.tourLocation(1000), nullptr);
}

TEST(EnvironmentKnowledgeBase, PrintsEveryValue) {
  const std::string path = src("tests/bad_kb/ok_minimal.dat");
  auto kb = EnvironmentKnowledgeBase::load(path);
  ASSERT_TRUE(kb.ok()) << kb.errorText();
  std::ostringstream out;
  kb.value().print(out);
  EXPECT_EQ(out.str(), "Environment knowledge base " + path +
                           ": 2 locations\n"
                           "Location 1\n"
                           "  Description                       Entrance\n"
                           "  Robot location pose (x y theta)   (0.5, 1, 90)\n"
                           "  Gesture target (x y z)            (1, 2, 0.8)\n"
                           "  Pre-gesture message English       Welcome to the lab\n"
                           "  Pre-gesture message isiZulu       Sawubona\n"
                           "  Pre-gesture message Kinyarwanda   Muraho\n"
                           "  Post-gesture message English      Please follow me\n"
                           "  Post-gesture message isiZulu      Siyabonga\n"
                           "  Post-gesture message Kinyarwanda  Murakoze\n"
                           "  Cultural knowledge                BowExtentRespect\n"
                           "Location 2\n"
                           "  Description                       The Pepper robot\n"
                           "  Robot location pose (x y theta)   (2.6, 8.1, -45)\n"
                           "  Gesture target (x y z)            (3.2, 8.4, 0.82)\n"
                           "  Pre-gesture message English       This is the Pepper robot\n"
                           "  Pre-gesture message isiZulu       Sawubona\n"
                           "  Pre-gesture message Kinyarwanda   Muraho\n"
                           "  Post-gesture message English      Thank you for visiting\n"
                           "  Post-gesture message isiZulu      Hamba kahle\n"
                           "  Post-gesture message Kinyarwanda  Murakoze\n"
                           "  Cultural knowledge                DeicticShape\n"
                           "Tour (2 locations): 1 2\n");
}

TEST(EnvironmentKnowledgeBase, ConfigurationSelectsTheBaseAndVerboseMode) {
  auto config = EnvironmentKnowledgeBase::loadConfiguration(src("data/environmentKnowledgeBaseConfiguration.ini"));
  ASSERT_TRUE(config.ok()) << config.errorText();
  EXPECT_EQ(config.value().knowledge_base, "environmentKnowledgeBaseInput.dat");
  EXPECT_EQ(config.value().knowledge_base_path, src("data/environmentKnowledgeBaseInput.dat"));
  EXPECT_FALSE(config.value().verbose_mode);

  std::ostringstream quiet;
  auto shipped =
      EnvironmentKnowledgeBase::loadFromConfiguration(src("data/environmentKnowledgeBaseConfiguration.ini"), quiet);
  ASSERT_TRUE(shipped.ok()) << shipped.errorText();
  EXPECT_EQ(shipped.value().tour().size(), 5u);
  EXPECT_EQ(quiet.str(), "");

  std::ostringstream verbose;
  auto minimal_kb = EnvironmentKnowledgeBase::loadFromConfiguration(src("tests/bad_kb/config_ok.ini"), verbose);
  ASSERT_TRUE(minimal_kb.ok()) << minimal_kb.errorText();
  std::ostringstream printed;
  minimal_kb.value().print(printed);
  EXPECT_EQ(verbose.str(), printed.str());
  EXPECT_NE(verbose.str().find("Tour (2 locations): 1 2\n"), std::string::npos);
}

// ----- Malformed inputs ---------------------------------------------------------------

TEST(EnvironmentKnowledgeBase, MissingFileAndDirectory) {
  auto missing = EnvironmentKnowledgeBase::load(src("tests/bad_kb/no_such.dat"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(
      relative(missing.errors()),
      std::vector<std::string>{"tests/bad_kb/no_such.dat:1:1: error: cannot read file: No such file or directory"});
  auto directory = EnvironmentKnowledgeBase::load(src("tests/bad_kb"));
  ASSERT_FALSE(directory.ok());
  EXPECT_EQ(relative(directory.errors()),
            std::vector<std::string>{"tests/bad_kb:1:1: error: is a directory, not a knowledge base file"});
  std::ostringstream out;
  auto no_config = EnvironmentKnowledgeBase::loadFromConfiguration(src("tests/bad_kb/none.ini"), out);
  ASSERT_FALSE(no_config.ok());
  EXPECT_EQ(relative(no_config.errors()),
            std::vector<std::string>{"tests/bad_kb/none.ini:1:1: error: cannot read file: No such file or directory"});
}

TEST(EnvironmentKnowledgeBase, BadNumber) {
  EXPECT_EQ(loadErrors("not_a_number"), expectedErrors("not_a_number"));
  EXPECT_EQ(loadErrors("coordinate_out_of_range"), expectedErrors("coordinate_out_of_range"));
}

TEST(EnvironmentKnowledgeBase, MissingKey) {
  EXPECT_EQ(
      loadErrors("missing_key"),
      std::vector<std::string>{"tests/bad_kb/missing_key.dat:13:1: error: location 2 has no `gestureTarget` entry"});
}

TEST(EnvironmentKnowledgeBase, OverlongStringIsAnErrorNotTruncated) {
  EXPECT_EQ(loadErrors("overlong_string"), expectedErrors("overlong_string"));
  const std::string at_limit(btgen::kb_limits::kMaxTextBytes, 'a');
  TempFile ok("at_limit.dat", replaced(minimal(), "1 Welcome to the lab", "1 " + at_limit));
  auto kb = EnvironmentKnowledgeBase::load(ok.path());
  ASSERT_TRUE(kb.ok()) << kb.errorText();
  EXPECT_EQ(kb.value().find(1)->preGestureMessage(Language::kEnglish), at_limit);
  TempFile over("over_limit.dat", replaced(minimal(), "1 Welcome to the lab", "1 " + at_limit + "b"));
  auto bad = EnvironmentKnowledgeBase::load(over.path());
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.errors(), std::vector<std::string>{
                              over.path() + ":5:33: error: `preGestureMessageEnglish` of location 1 is 256 bytes long; "
                                            "the runtime holds at most 255 bytes (UTF-8)"});
}

TEST(EnvironmentKnowledgeBase, BadTourCount) {
  EXPECT_EQ(
      loadErrors("tour_count_off_by_one"),
      std::vector<std::string>{
          "tests/bad_kb/tour_count_off_by_one.dat:24:19: error: the tour count is 3 but 2 location ids follow (1 2)"});
  EXPECT_EQ(loadErrors("tour_count_over_limit"), expectedErrors("tour_count_over_limit"));
  EXPECT_EQ(loadErrors("unknown_tour_id"), expectedErrors("unknown_tour_id"));
}

TEST(EnvironmentKnowledgeBase, EncodingAndEmptyFiles) {
  EXPECT_EQ(loadErrors("non_utf8"), expectedErrors("non_utf8"));
  EXPECT_EQ(loadErrors("control_character"), expectedErrors("control_character"));
  EXPECT_EQ(loadErrors("empty"), expectedErrors("empty"));
  TempFile big("big.dat", std::string(btgen::kb_limits::kMaxFileBytes + 1, '#'));
  auto kb = EnvironmentKnowledgeBase::load(big.path());
  ASSERT_FALSE(kb.ok());
  EXPECT_EQ(kb.errors(),
            std::vector<std::string>{
                big.path() + ":1:1: error: file is 131073 bytes; knowledge base files are limited to 131072 bytes"});
}

TEST(EnvironmentKnowledgeBase, AcceptsCrlfBomTabsAndCommas) {
  std::string text = replaced(minimal(), "2 3.2 8.4 0.82", "2\t3.2, 8.4 ,0.82");
  text = replaced(text, "tourSpecification 2 1 2", "tourSpecification 2, 1,2");
  std::string crlf = "\xEF\xBB\xBF";
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  TempFile file("crlf.dat", crlf);
  auto kb = EnvironmentKnowledgeBase::load(file.path());
  ASSERT_TRUE(kb.ok()) << kb.errorText();
  EXPECT_EQ(kb.value().find(2)->gesture_target, Eigen::Vector3d(3.2, 8.4, 0.82));
  EXPECT_EQ(kb.value().find(1)->description, "Entrance");
  EXPECT_EQ(kb.value().tour(), (std::vector<std::int32_t>{1, 2}));
}

// ----- Agreement with the Python linter on every bad input -----------------------------

std::vector<std::string> casesWithSuffix(const std::string& suffix) {
  std::vector<std::string> stems;
  for (const auto& entry : fs::directory_iterator(src("tests/bad_kb"))) {
    if (entry.path().extension() == suffix) stems.push_back(entry.path().stem().string());
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

/// "path:line:col: error:" of a diagnostic.
std::string position(const std::string& diagnostic) { return diagnostic.substr(0, diagnostic.find(": error: ") + 8); }

// The C++ reader stops before the checks across entries when a line is bad,
// so it may report fewer errors than the linter, but it rejects exactly the
// files the linter rejects and only at positions the linter reports; where
// it reports, the message is the linter's (did-you-mean hints aside).
void expectAgreement(const std::string& stem, const std::vector<std::string>& errors) {
  const std::vector<std::string> expected = expectedErrors(stem);
  EXPECT_EQ(errors.empty(), expected.empty()) << stem;
  std::set<std::string> positions;
  for (const std::string& e : expected) positions.insert(position(e));
  for (const std::string& e : errors) {
    EXPECT_EQ(positions.count(position(e)), 1u) << stem << ": C++ reported " << e;
    const bool hint = e.find("unknown") != std::string::npos;
    if (!hint) {
      EXPECT_NE(std::find(expected.begin(), expected.end(), e), expected.end()) << stem << ": " << e;
    }
  }
}

TEST(EnvironmentKnowledgeBase, AgreesWithTheLinterOnEveryBadBase) {
  const std::vector<std::string> stems = casesWithSuffix(".dat");
  ASSERT_GE(stems.size(), 30u);
  for (const std::string& stem : stems) {
    auto kb = EnvironmentKnowledgeBase::load(src("tests/bad_kb/" + stem + ".dat"));
    expectAgreement(stem, relative(kb.errors()));
  }
}

TEST(EnvironmentKnowledgeBase, AgreesWithTheLinterOnEveryBadConfiguration) {
  const std::vector<std::string> stems = casesWithSuffix(".ini");
  ASSERT_GE(stems.size(), 5u);
  for (const std::string& stem : stems) {
    auto config = EnvironmentKnowledgeBase::loadConfiguration(src("tests/bad_kb/" + stem + ".ini"));
    expectAgreement(stem, relative(config.errors()));
  }
}

}  // namespace
