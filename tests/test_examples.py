"""Every example runs headless: each script exits 0, each notebook executes without error.

Scripts in examples/ are small user programs, run as a user would. Notebooks
are executed cell by cell with nbclient on the ``python3`` kernel (the
interpreter running the tests, through ipykernel), in a temporary working
directory; they are stored without outputs.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent.parent / "examples"
EXAMPLES = sorted(HERE.glob("[0-9][0-9]_*.py"))
NOTEBOOKS = sorted(HERE.glob("[0-9][0-9]_*.ipynb"))


def test_there_are_examples():
    assert len(EXAMPLES) >= 1 and len(NOTEBOOKS) >= 1


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(script, tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(script), str(tmp_path / "out")], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr[-3000:]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_is_stored_without_outputs(path):
    nbformat = pytest.importorskip("nbformat")
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(not c.outputs and c.execution_count is None for c in code)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_runs(path, tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=180, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # raises CellExecutionError, with the cell and traceback, on any error
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    if path.name == "08_notebook.ipynb":  # the Generation shows as its thumbnail grid
        html = [o.data["text/html"] for o in outputs if "text/html" in o.get("data", {})]
        assert any('class="forcelayout-generation"' in h and "<img" in h for h in html)
