"""Build hook: map the repository's top-level folders into the wheel.

templates/, schema/, runtime/, cmake/ and bench/bench_main.cpp stay where
they are in the repository; building the package copies them (the files
btgen.resources.DATA_FILES names) to btgen/_data/ in the build directory,
where btgen.resources finds them once installed. Everything else is in
pyproject.toml.
"""

import os
import shutil
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "generator" / "btgen"))
import resources  # noqa: E402  (btgen/resources.py alone: no third-party imports)

sys.path.pop(0)


class build_py_with_data(build_py):
    def run(self):
        super().run()
        if getattr(self, "editable_mode", False):
            return  # an editable install runs from the checkout, which has the folders
        target = Path(self.build_lib) / "btgen" / resources.INSTALLED_DATA
        copied = 0
        for folder, pattern in resources.DATA_FILES:
            for src in sorted((HERE / folder).glob(pattern)):
                if src.is_file():
                    dst = target / src.relative_to(HERE)
                    dst.parent.mkdir(parents=True, exist_ok=True)
                    shutil.copyfile(src, dst)
                    copied += 1
        if not (target / "templates").is_dir():
            raise SystemExit(f"setup.py: no templates found under {HERE} (an sdist without MANIFEST.in's folders?)")
        print(f"setup.py: copied {copied} data files to {os.path.relpath(target, self.build_lib)}")


# <prefix>/share/cmake/btgen/: where find_package(btgen) looks without btgen_DIR (from PATH's
# <prefix>/bin or CMAKE_PREFIX_PATH); it reads the package in site-packages through `btgen --cmake-dir`.
setup(
    cmdclass={"build_py": build_py_with_data},
    data_files=[("share/cmake/btgen", ["cmake/share/btgenConfig.cmake", "cmake/btgenConfigVersion.cmake"])],
)
