"""Tools around the compiler: `btgen run` on either engine, benchmarks, `btgen graph`, and
the random mission generators used by the differential tests and fuzzing."""
