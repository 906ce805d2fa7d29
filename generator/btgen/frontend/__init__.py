"""Stage 1, the front end: secure XML reading, the XML Schema, semantic checks and enums.

Its output is a checked :class:`btgen.lang.model.Mission`; every user-facing error of the
mission text is reported here or in :mod:`btgen.ir`."""
