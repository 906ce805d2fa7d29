// Which locations of the knowledge base's tour are exhibits.
//
// The base's tour (tourSpecification, shipped: 1 4 3 2 5) lists every stop
// in visiting order. Its first stop is where Pepper starts (the document's
// "Pepper's starting location", with the welcome messages); its last stop is
// where the tour ends (the goodbye messages, and the door to point at). In
// between are the exhibits. So, for the Lab Tour:
//
//   home      the tour's first stop (LookUpHome; _GoHome goes back there)
//   exit      the tour's last stop  (LookUpEntrance: where V_EndTour leads the
//             visitor and points to the door)
//   exhibits  the stops strictly between them, in order (RetrieveListOfExhibits)
//
// The start and end locations are not exhibits: the robot does not walk to
// its own starting position and describe it. A tour of one or two stops has
// no exhibits (the robot goes straight to the end of the tour).
//
// On the blackboard the exhibits still to visit are one string: location ids
// separated by ";" ("4;3;2"), as missions/LabTour.xml documents.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "btgen/environment_knowledge_base.hpp"

namespace lab_tour_robot {

struct TourPlan {
  std::int32_t home = 0;
  std::int32_t exit = 0;
  std::vector<std::int32_t> exhibits;
};

/// The plan of the base's tour (the reader guarantees 1 to 20 existing stops).
[[nodiscard]] TourPlan plan_tour(const btgen::EnvironmentKnowledgeBase& kb);

/// "4;3;2".
[[nodiscard]] std::string exhibit_list_text(const std::vector<std::int32_t>& ids);

enum class ListRead : std::uint8_t { kTaken, kEmpty, kMalformed };

/// Takes the first id off a ";"-separated list: `id` gets it, `rest` the
/// list without it. Blanks around ids are allowed; an empty list (or only
/// blanks) is kEmpty; anything that is not a location id (1 to 2147483647,
/// digits only) is kMalformed.
[[nodiscard]] ListRead take_first_exhibit(std::string_view list, std::int32_t& id, std::string_view& rest) noexcept;

}  // namespace lab_tour_robot
