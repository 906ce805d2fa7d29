"""lang/hashorder.py: the order libstdc++'s unordered_map keeps a blackboard's keys in, which
Blackboard::debugMessage prints (4.10.0 prints it before `Blackboard::set` throws). Checked
against libstdc++ itself on random histories of insertions and erasures, with rehashes."""

import random
import shutil
import subprocess

import pytest

from btgen.lang.blackboard import Blackboard
from btgen.lang.hashorder import HashOrder, std_hash

_PROGRAM = r"""
#include <iostream>
#include <string>
#include <unordered_map>
int main() {
  std::string line;
  std::unordered_map<std::string, int> m;
  while (std::getline(std::cin, line)) {
    if (line == "=") {
      for (const auto& kv : m) std::cout << kv.first << ' ';
      std::cout << '\n';
      m.clear();
      m.rehash(0);
      m = std::unordered_map<std::string, int>();
    } else if (line[0] == '-') {
      m.erase(line.substr(1));
    } else if (line[0] == '#') {
      std::cout << std::hash<std::string>{}(line.substr(1)) << '\n';
    } else {
      m.emplace(line.substr(1), 0);
    }
  }
}
"""


@pytest.fixture(scope="module")
def libstdcxx(tmp_path_factory):
    if shutil.which("g++") is None:
        pytest.fail("g++ is needed (scripts/setup.sh installs it)")
    d = tmp_path_factory.mktemp("hashorder")
    (d / "m.cpp").write_text(_PROGRAM, encoding="utf-8")
    subprocess.run(["g++", "-O1", "-o", str(d / "m"), str(d / "m.cpp")], check=True)
    return str(d / "m")


def _histories(n):
    rng = random.Random(44)
    pool = ["n", "v", "x", "abc", "_autoremap", "goal", "a_key_longer_than_eight", "é"] + [f"k{i}" for i in range(60)]
    for _ in range(n):
        hist = []
        for _ in range(rng.randint(1, 90)):
            key = rng.choice(pool)
            hist.append((key, rng.random() > 0.2))
        yield hist


def test_hash_is_libstdcxx(libstdcxx):
    keys = ["", "n", "v", "abcdefgh", "abcdefghi", "a_key_longer_than_eight", "é"]
    script = "".join(f"#{k}\n" for k in keys)
    out = subprocess.run([libstdcxx], input=script, capture_output=True, text=True, check=True)
    assert out.stdout.split() == [str(std_hash(k)) for k in keys]


def test_order_is_libstdcxx(libstdcxx):
    hists = list(_histories(150))
    script = "".join("".join(("+" if ins else "-") + k + "\n" for k, ins in h) + "=\n" for h in hists)
    out = subprocess.run([libstdcxx], input=script, capture_output=True, text=True, check=True).stdout.splitlines()
    assert len(out) == len(hists)
    sizes = set()
    for h, line in zip(hists, out):
        order = HashOrder()
        for k, ins in h:
            order.insert(k) if ins else order.erase(k)
        sizes.add(len(order.order()))
        assert order.order() == line.split(), h
    assert max(sizes) > 29  # (two rehashes: 13 -> 29 -> 59 buckets)


def test_debug_message_follows_creations_and_unsets():
    bb = Blackboard()
    bb.create_entry("n", "int")
    bb.create_entry("v", "any")
    assert bb.debug_message() == "v (BT::AnyTypeAllowed)\nn (int)\n"  # (recorded: changing-types/)
    bb.unset("v")
    bb.create_entry("x", "double")
    order = HashOrder()
    for k, ins in (("n", True), ("v", True), ("v", False), ("x", True)):
        order.insert(k) if ins else order.erase(k)
    assert bb.debug_message() == "".join(f"{k} ({'int' if k == 'n' else 'double'})\n" for k in order.order())
