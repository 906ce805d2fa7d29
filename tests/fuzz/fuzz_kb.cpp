// libFuzzer target: the environment knowledge base reader (a .dat file).
// Every input must end in a base or in diagnostics, without a sanitizer
// report; a base that loads must answer every query consistently.
#include <cstdlib>
#include <sstream>

#include "btgen/environment_knowledge_base.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = btgen_fuzz::write_file("kb.dat", data, size);
  auto kb = btgen::EnvironmentKnowledgeBase::load(path);
  if (!kb) {
    if (kb.errors().empty()) std::abort();  // a failure must say why
    for (const auto& e : kb.errors()) {
      if (e.rfind(path + ":", 0) != 0) std::abort();  // every diagnostic names the file
    }
    return 0;
  }
  const auto& base = kb.value();
  for (const auto& loc : base.locations()) {
    if (base.find(loc.id) != &loc) std::abort();
  }
  for (std::size_t i = 0; i < base.tour().size(); ++i) {
    const auto* loc = base.tourLocation(i);
    if (loc == nullptr || loc->id != base.tour()[i]) std::abort();
  }
  if (base.tourLocation(base.tour().size()) != nullptr) std::abort();
  std::ostringstream out;
  base.print(out);
  return 0;
}
