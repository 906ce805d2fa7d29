// libFuzzer target: the Groot2 monitor's request parser (btgen::groot2::detail::
// parse_request, for_each_name), on any frames a client may send. The input is cut
// into frames by 2-byte little-endian length prefixes, at most kMaxRequestFrames of
// them (the server drops a peer that sends more). The oracle: every request is
// either understood or answered with a non-empty error, a BLACKBOARD request's names
// are its second frame cut at `;`, and nothing reads outside the frames (ASan).
// Hook requests (HOOK_INSERT, HOOK_REMOVE, BREAKPOINT_UNLOCK) go on to the hook JSON
// reader: a failure says why; what it accepts is in range, and HOOKS_DUMP's JSON of it
// reads back as the same hooks.
#include <array>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "btgen/groot2.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace g = btgen::groot2;
  std::array<std::string_view, g::kMaxRequestFrames> parts{};
  std::size_t n = 0;
  const char* p = reinterpret_cast<const char*>(data);
  while (size >= 2 && n < parts.size()) {
    std::size_t len = static_cast<std::size_t>(data[0]) | (static_cast<std::size_t>(data[1]) << 8);
    data += 2;
    p += 2;
    size -= 2;
    if (len > size) len = size;
    parts[n++] = std::string_view(p, len);
    data += len;
    p += len;
    size -= len;
  }
  const g::detail::Request r = g::detail::parse_request(parts.data(), n);
  using K = g::detail::Request::Kind;
  if (r.kind == K::kError && r.error.empty()) std::abort();  // an error reply says why
  if (r.kind != K::kError && (n == 0 || parts[0].size() != 6)) std::abort();
  if (r.kind == K::kBlackboard) {
    if (n != 2 || r.argument.data() != parts[1].data() || r.argument.size() != parts[1].size()) std::abort();
    std::size_t total = 0, names = 0;
    g::detail::for_each_name(r.argument, [&](std::string_view name) {
      if (name.find(';') != std::string_view::npos) std::abort();
      if (name.data() < r.argument.data() || name.data() + name.size() > r.argument.data() + r.argument.size())
        std::abort();
      total += name.size();
      ++names;
    });
    if (total + (names - 1) != r.argument.size()) std::abort();  // names and their separators
  }
  if (r.kind == K::kHookInsert) {
    std::vector<g::detail::HookSpec> specs;
    std::string_view error;
    if (!g::detail::parse_hooks(r.argument, specs, error)) {
      if (error.empty()) std::abort();
      return 0;
    }
    std::string dump = "[";
    for (const auto& h : specs) {
      if (h.position > 1 || static_cast<int>(h.desired) > 4) std::abort();
      g::detail::dump_hook(dump, h);
    }
    dump += "]";
    std::vector<g::detail::HookSpec> again;
    if (!g::detail::parse_hooks(dump, again, error) || again.size() != specs.size()) std::abort();
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const auto &a = specs[i], &b = again[i];
      if (a.uid != b.uid || a.position != b.position || a.enabled != b.enabled || a.once != b.once ||
          a.breakpoint != b.breakpoint || a.desired != b.desired)
        std::abort();
    }
  }
  if (r.kind == K::kHookRemove || r.kind == K::kBreakpointUnlock) {
    g::detail::HookSpec ref;
    std::string_view error;
    if (!g::detail::parse_hook_ref(r.argument, r.kind == K::kBreakpointUnlock, ref, error) && error.empty())
      std::abort();
  }
  return 0;
}
