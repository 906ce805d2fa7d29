// The phrase table: what the Lab Tour's speech nodes without a location say.
//
// A speech node names its phrase with its `message` port; the defaults are
// in missions/LabTour.xml's TreeNodesModel (WelcomeSpeech says `welcome`,
// ...). Three phrases are the knowledge base's own words, so that every
// message of the base is said during the tour, in the base's languages:
//
//   welcome      the home location's pre- and post-gesture messages
//                ("Welcome to the robotics lab ...", "I will give you a short tour ...")
//   end_of_tour  the exit location's pre-gesture message ("I hope you enjoyed the tour")
//   goodbye      the exit location's post-gesture message ("See you again soon")
//
// The others are written here. Their isiZulu and Kinyarwanda texts are
// empty: no translation checked by a speaker exists yet, and an invented one
// would be worse than none. The robot then says the English text after the
// marker "[no isiZulu translation]" (speech.hpp). To add a translation, put
// it in the second (isiZulu) or third (Kinyarwanda) column.
#include <vector>

#include "speech.hpp"

namespace lab_tour_robot {

const std::vector<Phrase>& phrase_table() {
  //                English                                              isiZulu  Kinyarwanda
  static const std::vector<Phrase> kTable = {
      {"welcome", PhraseSource::kHomeMessages, {}},
      {"query_tour", PhraseSource::kTable, {{"Would you like to take the tour?", "", ""}}},
      {"say_yes_no", PhraseSource::kTable, {{"Please answer yes or no.", "", ""}}},
      {"press_yes_no", PhraseSource::kTable, {{"Please press Yes or No on my tablet.", "", ""}}},
      {"maybe_another_time", PhraseSource::kTable, {{"No problem. Maybe another time.", "", ""}}},
      {"follow_me", PhraseSource::kTable, {{"Please follow me.", "", ""}}},
      {"end_of_tour", PhraseSource::kExitPreMessage, {}},
      {"here_is_the_door", PhraseSource::kTable, {{"Here is the door.", "", ""}}},
      {"goodbye", PhraseSource::kExitPostMessage, {}},
  };
  return kTable;
}

}  // namespace lab_tour_robot
