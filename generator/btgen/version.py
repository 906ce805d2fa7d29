"""Version numbers of the generator and of the runtime ABI it targets."""

__version__ = "0.3.0"

# Bumped whenever generated code needs a different runtime. The generated
# header static_asserts that runtime/include/btgen/version.hpp agrees.
RUNTIME_ABI = 9
