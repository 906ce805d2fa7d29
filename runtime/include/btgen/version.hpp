// btgen runtime: version numbers shared by every generated mission.
#pragma once

namespace btgen {

// The runtime ABI generated code is written against. Every generated header
// static_asserts that this number equals the one its generator targeted
// (btgen.version.RUNTIME_ABI); a mismatch means: regenerate the mission.
inline constexpr int kRuntimeAbi = 9;

inline constexpr const char* kRuntimeVersion = "0.3.0";

}  // namespace btgen
