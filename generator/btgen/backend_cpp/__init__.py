"""Stage 3, the C++ back end: the IR through the Jinja2 templates into C++17, and the naming
layer that makes every mission identifier a safe C++ identifier."""
