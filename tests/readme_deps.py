#!/usr/bin/env python3
"""readme_deps.py ROOT: the README's Quick start package sets (build, tests,
dev) are the same packages as .ci/run's build_deps, test_deps and dev_deps,
set for set, and the README's install command installs $build and $tests.
Prints each difference and exits 1; 0 when they agree."""
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "."
readme = open(f"{root}/README.md", encoding="utf-8").read()
ci = open(f"{root}/.ci/run", encoding="utf-8").read()
fail = 0
for name, ci_name in (("build", "build_deps"), ("tests", "test_deps"), ("dev", "dev_deps")):
    m = re.search(rf'^{name}="([^"]*)"$', readme, re.M)
    c = re.search(rf"^{ci_name}=\(([^)]*)\)", ci, re.M)
    if not m or not c:
        print(f"set {name}: missing from {'README.md' if not m else '.ci/run'}")
        fail = 1
        continue
    a, b = set(m.group(1).split()), set(c.group(1).split())
    if a != b:
        print(f"set {name}: only in README.md: {sorted(a - b)}; only in .ci/run: {sorted(b - a)}")
        fail = 1
if not re.search(r"apt-get install -y --no-install-recommends \$build \$tests &&", readme):
    print("README.md: the Quick start command does not install $build $tests")
    fail = 1
sys.exit(fail)
