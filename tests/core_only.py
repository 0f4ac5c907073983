"""Run in an environment with only the core dependencies (``make core-check``).

``import forcelayout`` must work and import no optional extra; importing an
optional subpackage must fail with an ImportError that names its extra.
"""

import importlib
import sys

import forcelayout
import forcelayout.validate  # the V loop is core; its VLM judge is not

plan = forcelayout.examples.load_example("bedroom")
for heavy in ("openai", "trimesh", "pxr", "mujoco", "torch"):
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
print(f"core-only import ok: forcelayout {forcelayout.__version__}, plan {plan.name!r} loads")
