"""The documentation runs and is complete.

(a) Every ```python block of docs/*.md and README.md runs, each in a fresh
namespace inside a temporary working directory. Blocks marked with the comment
``# needs: llm-endpoint`` and blocks that start a ProcessPoolExecutor with more
than 2 workers (or with the default, all cores) are skipped. Blocks of one page
run in page order in this process, so a rule plugin registered by one block is
seen by the next; rules a page registers are removed afterwards.

(b) Every public name (``__all__``) of forcelayout and its public modules and
subpackages appears in docs/api.md.

(c) The examples in the docstrings of every module of forcelayout run
(doctest); a module whose optional extra is missing is skipped.
"""

from __future__ import annotations

import importlib
import json
import re
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.glob("*.md")) + [ROOT / "README.md"]
LLM_MARKER = "# needs: llm-endpoint"
FENCE = re.compile(r"^```python[^\n]*\n(.*?)^```", re.S | re.M)
JSON_FENCE = re.compile(r"^```json[^\n]*\n(.*?)^```", re.S | re.M)
POOL = re.compile(r"ProcessPoolExecutor\(\s*(?:max_workers\s*=\s*)?(\d*)")
#: The keys of a line of a dataset's index.jsonl (tests/test_dataset.py checks real ones).
INDEX_LINE_KEYS = {"plan", "layout", "sample", "seed", "files", "rule_satisfaction",
                   "rejected_before", "checks"}
#: Blocks that need a cluster: a scheduler queue, Ray, or more local workers than CI has.
CLUSTER = re.compile(r"SLURMCluster|^\s*(?:import|from) ray\b|LocalCluster\(n_workers=([3-9]|\d\d)",
                     re.M)

#: Modules and subpackages whose ``__all__`` docs/api.md must cover.
PUBLIC_MODULES = (
    "forcelayout",
    "forcelayout.plan",
    "forcelayout.rules",
    "forcelayout.sampling",
    "forcelayout.layout",
    "forcelayout.solver",
    "forcelayout.forces",
    "forcelayout.initial",
    "forcelayout.pipeline",
    "forcelayout.hierarchy",
    "forcelayout.surfaces",
    "forcelayout.validate",
    "forcelayout.sanity",
    "forcelayout.autofix",
    "forcelayout.relax",
    "forcelayout.diagnose",
    "forcelayout.render",
    "forcelayout.views",
    "forcelayout.metrics",
    "forcelayout.baselines",
    "forcelayout.testing",
    "forcelayout.examples",
    "forcelayout.errors",
    "forcelayout.report",
    "forcelayout.geometry",
    "forcelayout.rules.physical",
    "forcelayout.rules.shaping",
    "forcelayout.bindings",
    "forcelayout.options",
    "forcelayout.sources",
    "forcelayout.access",
    "forcelayout.clearance",
    "forcelayout.repair",
    "forcelayout.baselines",
    "forcelayout.dataset",
    "forcelayout.validate.loop",
)
#: Optional subpackages: checked only when their extra is installed.
OPTIONAL_MODULES = (("forcelayout.export", "trimesh"), ("forcelayout.llm", "openai"),
                    ("forcelayout.validate.vlm", "openai"),
                    ("forcelayout.grounding", "trimesh"))


def python_blocks(page: Path) -> list[tuple[int, str]]:
    """Every ```python block of a page with the line number of its fence."""
    text = page.read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start()) + 1, m.group(1)) for m in FENCE.finditer(text)]


def skip_reason(code: str) -> str | None:
    """Why a block cannot run in the test suite, or None when it can."""
    if LLM_MARKER in code:
        return "needs an LLM endpoint"
    if CLUSTER.search(code):
        return "starts a cluster"
    for workers in POOL.findall(code):
        if not workers or int(workers) > 2:
            return "starts a process pool with more than 2 workers"
    return None


PAGES_WITH_CODE = [p for p in PAGES if python_blocks(p)]


def test_pages_have_code_blocks():
    assert len(PAGES_WITH_CODE) >= 5, [p.name for p in PAGES_WITH_CODE]


@pytest.fixture
def clean_registry():
    """The rule registry of a fresh install, restored afterwards.

    Installed third-party plugins (such as examples/plugin, which provides
    ``near_plant`` too) are hidden while the blocks run, as a reader who
    follows the docs does not have them; rules the blocks register are removed.
    """
    from forcelayout import rules

    registry, instances = dict(rules._registry), dict(rules._instances)
    loaded = rules._entry_points_loaded
    for name, entry in registry.items():
        module = entry if isinstance(entry, str) else entry.__module__
        if not module.startswith("forcelayout."):
            rules.unregister(name)
    yield
    rules._registry.clear()
    rules._registry.update(registry)
    rules._instances.clear()
    rules._instances.update(instances)
    rules._entry_points_loaded = loaded


@pytest.mark.parametrize("page", PAGES_WITH_CODE, ids=lambda p: p.name)
def test_code_blocks_run(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                         clean_registry: None):
    import matplotlib.pyplot as plt

    blocks = python_blocks(page)
    if all(skip_reason(code) for _, code in blocks):
        pytest.skip(f"{page.name}: every block needs an endpoint, many cores or a cluster")
    monkeypatch.chdir(tmp_path)
    ran = 0
    for line, code in blocks:
        if skip_reason(code):
            continue
        namespace: dict[str, object] = {"__name__": f"docs_{page.stem}_{line}"}
        try:
            exec(compile(code, f"{page.name}:{line}", "exec"), namespace)
        except Exception as exc:
            pytest.fail(f"{page.name}, block at line {line}: {type(exc).__name__}: {exc}")
        finally:
            plt.close("all")
        ran += 1
    assert ran > 0


def test_skip_rules():
    assert skip_reason(f"x = 1  {LLM_MARKER}") == "needs an LLM endpoint"
    assert skip_reason("ProcessPoolExecutor()") is not None
    assert skip_reason("ProcessPoolExecutor(8)") is not None
    assert skip_reason("ProcessPoolExecutor(max_workers=4)") is not None
    assert skip_reason("ProcessPoolExecutor(2)") is None
    assert skip_reason("import forcelayout") is None
    assert skip_reason("LocalCluster(n_workers=8)") == "starts a cluster"
    assert skip_reason("LocalCluster(n_workers=2)") is None
    assert skip_reason("cluster = SLURMCluster(cores=32)") == "starts a cluster"
    assert skip_reason("from ray.util.concurrent.futures import RayExecutor") == "starts a cluster"
    assert skip_reason("import forcelayout\nimport ray\n") == "starts a cluster"
    assert skip_reason("x = array  # no ray here") is None


def _public_names() -> list[tuple[str, str]]:
    names = []
    for module in PUBLIC_MODULES:
        names += [(module, n) for n in importlib.import_module(module).__all__]
    for module, dependency in OPTIONAL_MODULES:
        try:
            importlib.import_module(dependency)
        except ImportError:
            continue
        names += [(module, n) for n in importlib.import_module(module).__all__]
    return names


def test_api_page_lists_every_public_name():
    api = (DOCS / "api.md").read_text(encoding="utf-8")
    missing = [
        f"{module}.{name}"
        for module, name in _public_names()
        if not re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", api)
    ]
    assert not missing, f"docs/api.md does not mention: {', '.join(missing)}"


def test_api_page_names_each_module():
    api = (DOCS / "api.md").read_text(encoding="utf-8")
    modules = PUBLIC_MODULES[1:] + tuple(m for m, _ in OPTIONAL_MODULES)
    missing = [m for m in modules if f"`{m}`" not in api]
    assert not missing, f"docs/api.md has no section for: {', '.join(missing)}"


def test_index_lists_every_page():
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    linked = set(re.findall(r"\]\(([^)#]+\.md)\)", index))
    pages = {p.name for p in DOCS.glob("*.md")} - {"index.md"}
    assert linked == pages, f"index.md links {sorted(linked)}, docs/ holds {sorted(pages)}"


def test_json_blocks_are_valid_plans_and_rules():
    """A JSON block holding a plan validates as a Plan; one holding a rule, as a RuleSpec."""
    import forcelayout as fl

    seen = 0
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for m in JSON_FENCE.finditer(text):
            where = f"{page.name}:{text.count(chr(10), 0, m.start()) + 1}"
            data = json.loads(m.group(1))
            if isinstance(data, dict) and {"room", "objects"} <= data.keys():
                fl.Plan.from_dict(data)
            elif isinstance(data, dict) and "rule" in data:
                fl.RuleSpec.model_validate(data)
            elif isinstance(data, dict) and "layout" in data:  # a dataset's index line
                assert data.keys() == INDEX_LINE_KEYS, where
            else:
                pytest.fail(f"{where}: a JSON block that is neither a plan, a rule nor an "
                            "index line")
            seen += 1
    assert seen >= 1


def test_llm_blocks_are_marked_or_offline():
    """A block that talks to a server must carry the marker; offline ones may run."""
    for page in PAGES:
        for line, code in python_blocks(page):
            needs_server = "base_url=" in code or "OpenAIChatClient(" in code
            if needs_server:
                assert LLM_MARKER in code, f"{page.name}:{line} needs the marker {LLM_MARKER!r}"



def _modules() -> list[str]:
    import pkgutil

    import forcelayout

    return sorted(m.name for m in pkgutil.walk_packages(forcelayout.__path__, "forcelayout."))


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples_run(name: str, monkeypatch: pytest.MonkeyPatch, tmp_path: Path):
    import doctest

    try:
        module = importlib.import_module(name)
    except ImportError as e:  # an optional extra that is not installed
        pytest.skip(f"{name}: {e}")
    monkeypatch.chdir(tmp_path)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
                             verbose=False, report=True)
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed"


def test_concepts_page_lists_the_categories_with_an_access_zone():
    from forcelayout.access import CATEGORY_ACCESS

    text = (DOCS / "concepts.md").read_text()
    missing = [w for w in CATEGORY_ACCESS if f"`{w}`" not in text]
    assert not missing, f"docs/concepts.md does not list {missing}"
