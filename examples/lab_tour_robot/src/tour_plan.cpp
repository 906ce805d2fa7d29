#include "tour_plan.hpp"

namespace lab_tour_robot {

namespace {

bool is_blank(char c) noexcept { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) noexcept {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

}  // namespace

TourPlan plan_tour(const btgen::EnvironmentKnowledgeBase& kb) {
  TourPlan plan;
  const std::vector<std::int32_t>& tour = kb.tour();
  if (tour.empty()) return plan;
  plan.home = tour.front();
  plan.exit = tour.back();
  if (tour.size() > 2) plan.exhibits.assign(tour.begin() + 1, tour.end() - 1);
  return plan;
}

std::string exhibit_list_text(const std::vector<std::int32_t>& ids) {
  std::string text;
  for (std::int32_t id : ids) {
    if (!text.empty()) text += ';';
    text += std::to_string(id);
  }
  return text;
}

ListRead take_first_exhibit(std::string_view list, std::int32_t& id, std::string_view& rest) noexcept {
  list = trim(list);
  if (list.empty()) return ListRead::kEmpty;
  const std::size_t semi = list.find(';');
  const std::string_view first = trim(list.substr(0, semi));
  rest = semi == std::string_view::npos ? std::string_view() : list.substr(semi + 1);
  if (first.empty() || first.size() > 10 || first[0] == '0') return ListRead::kMalformed;
  std::int64_t value = 0;
  for (char c : first) {
    if (c < '0' || c > '9') return ListRead::kMalformed;
    value = value * 10 + (c - '0');
  }
  if (value > 2147483647) return ListRead::kMalformed;
  // "4;" leaves an empty rest, which is fine; "4;;3" leaves ";3", malformed when read.
  id = static_cast<std::int32_t>(value);
  return ListRead::kTaken;
}

}  // namespace lab_tour_robot
