"""Scripts -> C++, in the modules of this package:

- ``compiler``: ScriptCompiler, a typed script (ir/script_types.py) as the straight-line body
  of one C++ function, and ``compile_scripts``, every script of a mission;
- ``writer``: CodeWriter (lines, temporaries, error exits; also the base of the data side's
  port readers and writers), Val and SlotView, a value as a btgen::dyn::Ref;
- ``stores``: stores into a typed blackboard entry (4.6.2's `_store`).

The C++ literals they print come from ``backend_cpp/literals.py``.
"""

from btgen.backend_cpp.script_cpp.compiler import CompiledScript, ScriptCompiler, compile_script, compile_scripts
from btgen.backend_cpp.script_cpp.writer import CPP_SCALAR, CodeWriter, ScriptContext, SlotView, Val, to_ref

__all__ = [
    "CPP_SCALAR",
    "CodeWriter",
    "CompiledScript",
    "ScriptCompiler",
    "ScriptContext",
    "SlotView",
    "Val",
    "compile_script",
    "compile_scripts",
    "to_ref",
]
