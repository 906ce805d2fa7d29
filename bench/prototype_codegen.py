"""Experiment, not part of btgen: one generated C++ function per node instead of the table engine,
to measure what that redesign would cost (issue 7 report). Reproduce:

    btgen compile bench/missions/balanced_1000.xml -o /tmp/p
    python bench/prototype_codegen.py bench/missions/balanced_1000.xml /tmp/p/proto.hpp
    g++ -std=c++17 -O2 -DNDEBUG -DBTGEN_MISSION_HEADER='"proto.hpp"' -DBTGEN_MISSION_TEMPLATE=proto::Mission \
        -Iruntime/include -I/tmp/p bench/bench_main.cpp runtime/src/testing/alloc_counter.cpp -o /tmp/p/proto
    # then callgrind /tmp/p/proto N for two N, as bench/run_benchmarks.py does

Measured at 5054c99 (g++ 12 -O2, leaves made opaque to the optimiser by returning a volatile):
7.8 instructions per visited node on balanced_1000 (table engine: 78.9), 11.7 on balanced_10000;
g++ needs 11.7 s for 1,000 nodes and 316 s for 10,000 (table engine: 1.6 s and 4.4 s). With
the inline InstantLeaves of bench_main.cpp the compiler folds much of the tree away (reactive_1000:
1.0 per node), so compare with opaque leaves. Status-change traces equal the table engine's on the
balanced, reactive and SubTree missions with instant leaves.

Covers Sequence, Fallback, ReactiveSequence, ReactiveFallback, Inverter, SubTree, AlwaysSuccess,
AlwaysFailure, Action, Condition with BehaviorTree.CPP 4.6.2's tick rules as engine.hpp has them
(halting a RUNNING child is a call to the table engine's generic halt, which instant leaves never reach).
The class has the generated mission's interface (Leaves, Clock, Observer; tick(), node_count()).
"""
import sys

sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parents[1] / "generator"))
from btgen.backend_cpp import naming  # noqa: E402
from btgen.compiler import mission_stem  # noqa: E402
from btgen.frontend.loader import load_mission  # noqa: E402
from btgen.ir.lower import lower  # noqa: E402

path, out = sys.argv[1], sys.argv[2]
prog = lower(load_mission(path))
stem = mission_stem(path)
ns, cls = naming.namespace_name(stem), naming.pascal_case(stem)
counters = {}
nslots = 0
for n in prog.nodes:
    if n.kind in ("Sequence", "Fallback"):
        counters[n.index] = nslots
        nslots += 2

L = []
w = L.append
w(f'#pragma once\n#include "{naming.header_name(stem)}"\n')
w("namespace proto {")
w("using btgen::Status;")
w("template <class Leaves, class Clock = btgen::ManualClock, class Observer = btgen::NoObserver>")
w("class Mission {")
w(" public:")
w(f"  using Spec = {ns}::detail::Spec;")
w("  explicit Mission(Leaves& l, Clock c = Clock{}, Observer o = Observer{}) noexcept : leaves_(&l), clock_(c), obs_(o) {}")
w(f"  static constexpr std::size_t node_count() noexcept {{ return {len(prog.nodes)}; }}")
w("  [[nodiscard]] Status tick() noexcept { const Status s = x0(); if (btgen::is_completed(s)) set(0, Status::IDLE); return s; }")
w(" private:")
w("  static constexpr Status san(Status s) noexcept { return (s == Status::SUCCESS || s == Status::FAILURE || s == Status::RUNNING) ? s : Status::FAILURE; }")
w("  void set(std::uint16_t n, Status s) noexcept { const Status p = st_[n]; st_[n] = s; if (p != s) obs_.on_status_change(Spec::kNodes[n], p, s); }")
w("  [[gnu::noinline]] void halt_slow(std::uint16_t n) noexcept { set(n, Status::IDLE); }  // RUNNING subtrees: not reached here")
w("  void halt_child(std::uint16_t c) noexcept { if (st_[c] == Status::RUNNING) halt_slow(c); set(c, Status::IDLE); }")


def reset_children(n):
    return " ".join(f"halt_child({c});" for c in n.children)


for n in prog.nodes:
    i, k, ch = n.index, n.kind, n.children
    # executeTick
    body = [f"const Status s = t{i}();", f"if (s != Status::SKIPPED) set({i}, s);"]
    if k in ("Inverter", "SubTree"):
        body.append(f"if (btgen::is_completed(st_[{ch[0]}])) set({ch[0]}, Status::IDLE);")
    body.append("return s;")
    w(f"  Status x{i}() noexcept {{ {' '.join(body)} }}")
    if k in ("Sequence", "Fallback"):
        seq = k == "Sequence"
        go_on, stop = ("SUCCESS", "FAILURE") if seq else ("FAILURE", "SUCCESS")
        slot = counters[i]
        w(f"  Status t{i}() noexcept {{")
        w(f"    std::int32_t& idx = c_[{slot}]; std::int32_t& skipped = c_[{slot + 1}];")
        w(f"    if (!btgen::is_active(st_[{i}])) skipped = 0;")
        w(f"    set({i}, Status::RUNNING);")
        w("    for (;;) {")
        w("      Status s;")
        w("      switch (idx) {")
        for pos, c in enumerate(ch):
            w(f"        case {pos}: s = x{c}(); break;")
        w("        default: goto end;")
        w("      }")
        w("      if (s == Status::RUNNING) return Status::RUNNING;")
        w(f"      if (s == Status::{stop}) {{ {reset_children(n)} idx = 0; return Status::{stop}; }}")
        w("      ++idx; if (s == Status::SKIPPED) ++skipped;")
        w("    }")
        w("  end: {")
        w(f"    const bool all_skipped = skipped == {len(ch)};")
        w(f"    {reset_children(n)} idx = 0; skipped = 0;")
        w(f"    return all_skipped ? Status::SKIPPED : Status::{go_on};")
        w("  } }")
    elif k in ("ReactiveSequence", "ReactiveFallback"):
        seq = k == "ReactiveSequence"
        stop, last = ("FAILURE", "SUCCESS") if seq else ("SUCCESS", "FAILURE")
        w(f"  Status t{i}() noexcept {{")
        w(f"    set({i}, Status::RUNNING); bool all_skipped = true; Status s;")
        for pos, c in enumerate(ch):
            others = " ".join(f"halt_child({o});" for o in ch if o != c)
            w(f"    s = x{c}(); if (s != Status::SKIPPED) all_skipped = false;")
            w(f"    if (s == Status::RUNNING) {{ {others} return s; }}")
            w(f"    if (s == Status::{stop}) {{ {reset_children(n)} return s; }}")
            w(f"    if (s == Status::SKIPPED) halt_child({c});")
        w(f"    {reset_children(n)} return all_skipped ? Status::SKIPPED : Status::{last};")
        w("  }")
    elif k == "Inverter":
        c = ch[0]
        w(f"  Status t{i}() noexcept {{ set({i}, Status::RUNNING); const Status s = x{c}();"
          f" if (s == Status::SUCCESS) {{ halt_child({c}); return Status::FAILURE; }}"
          f" if (s == Status::FAILURE) {{ halt_child({c}); return Status::SUCCESS; }} return s; }}")
    elif k == "SubTree":
        c = ch[0]
        w(f"  Status t{i}() noexcept {{ if (st_[{i}] == Status::IDLE) set({i}, Status::RUNNING); const Status s = x{c}();"
          f" if (btgen::is_completed(s)) halt_child({c}); return s; }}")
    elif k == "AlwaysSuccess":
        w(f"  Status t{i}() noexcept {{ return Status::SUCCESS; }}")
    elif k == "AlwaysFailure":
        w(f"  Status t{i}() noexcept {{ return Status::FAILURE; }}")
    elif k == "Action":
        w(f"  Status t{i}() noexcept {{ const Status st = st_[{i}];"
          f" if (st == Status::IDLE) return san(Spec::on_start(*leaves_, Spec::kNodes[{i}]));"
          f" if (st == Status::RUNNING) return san(Spec::on_running(*leaves_, Spec::kNodes[{i}])); return st; }}")
    elif k == "Condition":
        w(f"  Status t{i}() noexcept {{ return san(Spec::check(*leaves_, Spec::kNodes[{i}])); }}")
    else:
        raise SystemExit(f"prototype: no code for {k}")
w("  Leaves* leaves_;")
w("  Clock clock_;")
w("  Observer obs_;")
w(f"  std::array<Status, {len(prog.nodes)}> st_{{}};")
w(f"  std::array<std::int32_t, {max(nslots, 1)}> c_{{}};")
w("};")
w("}  // namespace proto")
open(out, "w").write("\n".join(L) + "\n")
