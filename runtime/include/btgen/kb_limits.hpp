// Limits of the environment knowledge base, shared by the C++ reader
// (environment_knowledge_base.hpp) and the Python linter
// (generator/btgen/kb/lint.py: KB_MAX_*) and schema/environment_knowledge_base.xsd.
// tests/python/test_kb.py checks that all three agree: change them together.
//
// The reader stores text in std::string, so these are not buffer sizes: they
// bound what a robot with fixed buffers (D5.4.2: char[STRING_LENGTH],
// MAX_CULTURAL_KEYS, MAX_NUMBER_OF_TOUR_LOCATIONS) can hold, and a file
// beyond them is rejected with an error instead of being truncated.
#ifndef BTGEN_KB_LIMITS_HPP
#define BTGEN_KB_LIMITS_HPP

#include <cstddef>
#include <cstdint>

namespace btgen::kb_limits {

/// Largest .dat or .ini file, in bytes (the Lab Tour base is about 4 kB).
inline constexpr std::size_t kMaxFileBytes = 131072;
/// Longest description or message, in UTF-8 bytes, without a terminator.
inline constexpr std::size_t kMaxTextBytes = 255;
/// Most cultural knowledge keys per location.
inline constexpr std::size_t kMaxCulturalKeys = 10;
/// Longest cultural knowledge key, in bytes (keys are ASCII).
inline constexpr std::size_t kMaxCulturalKeyBytes = 63;
/// Most locations in the tour.
inline constexpr std::size_t kMaxTourLocations = 20;
/// Largest location id (ids start at 1).
inline constexpr std::int32_t kMaxLocationId = 2147483647;
/// Largest magnitude of a coordinate: metres, or degrees for theta.
inline constexpr double kMaxAbsCoordinate = 1000000.0;

}  // namespace btgen::kb_limits

#endif  // BTGEN_KB_LIMITS_HPP
