"""Run in an environment with only the core dependencies (``make core-check``).

``import forcelayout`` must work and import no optional extra; importing an
optional subpackage must fail with an ImportError that names its extra; a
sample runs on the numpy forms where the ``fast`` extra's kernels are absent.
"""

import importlib
import os
import sys

import forcelayout
import forcelayout.validate  # the V loop is core; its VLM judge is not

plan = forcelayout.examples.load_example("bedroom")
for heavy in ("openai", "trimesh", "pxr", "mujoco", "torch", "numba"):
    if heavy in sys.modules:
        raise SystemExit(f"import forcelayout imported the optional package {heavy!r}")
for module, extra in (("forcelayout.llm", "llm"), ("forcelayout.export", "export"),
                      ("forcelayout.validate.vlm", "vlm")):
    try:
        importlib.import_module(module)
    except ImportError as e:
        if f"forcelayout[{extra}]" not in str(e):
            raise SystemExit(f"{module}: ImportError does not name the extra: {e}") from e
    else:
        raise SystemExit(f"{module} imported without its extra installed")
# without the fast extra the numpy forms compute the footprint geometry; asking for the
# compiled kernels names the extra
layout = forcelayout.solve(plan, 0)
if forcelayout._compiled.kernels() is not None or not layout.report.valid:
    raise SystemExit("a sample without numba did not run on the numpy forms")
forcelayout._compiled._LOADED.clear()
os.environ[forcelayout._compiled.ENV] = "1"
try:
    forcelayout._compiled.kernels()
except ImportError as e:
    if "forcelayout[fast]" not in str(e):
        raise SystemExit(f"FORCELAYOUT_COMPILED=1: ImportError does not name the extra: {e}") \
            from e
else:
    raise SystemExit("FORCELAYOUT_COMPILED=1 without numba did not raise")
print(f"core-only import ok: forcelayout {forcelayout.__version__}, plan {plan.name!r} loads")
