"""Quick start: one bundled plan, several layouts, pictures and JSON.

Shows the core loop of forcelayout: load a plan, generate layouts with a
fixed seed, look at why samples were rejected, and save each layout as JSON
and a top-down PNG. Needs only the core install.

Run: ``python examples/01_quickstart.py [OUT_DIR]``
"""

# %%
import sys
import tempfile
from pathlib import Path

import forcelayout as fl

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
out.mkdir(parents=True, exist_ok=True)

# %% A plan: room, objects, rules. Bundled ones load by name.
plan = fl.load_plan("bedroom")
print(f"{plan.name}: {len(plan.objects)} objects, {len(plan.rules)} rules")

# %% One plan -> many layouts. Same seed, same layouts.
result = fl.generate(plan, 3, seed=0)
summary = result.summary()
print(f"{summary['accepted']} layouts from {summary['attempted']} samples, "
      f"{summary['valid_fraction']:.0%} valid, {summary['mean_rule_satisfaction']:.0%} rules met")

# %% Each layout: poses, a per-rule report, a picture.
for k, layout in enumerate(result):
    unmet = [f"{r.rule}({r.object})" for r in layout.rule_report() if r.satisfied is False]
    print(f"layout {k}: seed {layout.seed}, unmet rules: {unmet or 'none'}")
    layout.save(out / f"bedroom_{k}.json")
    layout.picture(out / f"bedroom_{k}.png")
print(f"wrote {out}")
