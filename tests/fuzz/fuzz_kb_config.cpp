// libFuzzer target: the knowledge base configuration reader (a .ini file),
// then the base it names (a valid one is written beside it).
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "btgen/environment_knowledge_base.hpp"
#include "fuzz_common.hpp"

#ifndef BTGEN_FUZZ_VALID_KB
#error "define BTGEN_FUZZ_VALID_KB as the path of a valid knowledge base"
#endif

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::FILE* in = std::fopen(BTGEN_FUZZ_VALID_KB, "rb");
  if (in == nullptr) std::abort();
  std::string text;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, in)) > 0) text.append(buf, n);
  std::fclose(in);
  btgen_fuzz::write_file("environmentKnowledgeBaseInput.dat", reinterpret_cast<const std::uint8_t*>(text.data()),
                         text.size());
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = btgen_fuzz::write_file("kb.ini", data, size);
  auto config = btgen::EnvironmentKnowledgeBase::loadConfiguration(path);
  if (!config && config.errors().empty()) std::abort();
  std::ostringstream verbose;
  auto kb = btgen::EnvironmentKnowledgeBase::loadFromConfiguration(path, verbose);
  if (!kb && kb.errors().empty()) std::abort();
  if (kb && !config) std::abort();  // a base from a configuration that did not load
  return 0;
}
