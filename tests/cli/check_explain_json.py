#!/usr/bin/env python3
"""partc --explain=json on tests/cli/scene_damped.part: the facts of a scene,
read as a tool would read them; on tests/golden/observed_steps.part, which
statements run only on observed steps; and on FUSED (tests/e2e/fused_pass.part),
its fused pass.

    check_explain_json.py PARTC SCENE OBSERVED_STEPS FUSED
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path


def facts(partc, scene, *extra):
    out = subprocess.run([partc, scene, "--explain=json", *extra], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def expect(condition, what):
    if not condition:
        sys.exit("--explain=json: " + what)


def main():
    partc, scene, observed_scene, fused_scene = sys.argv[1:5]
    all_three = facts(partc, scene)
    kept = [e["name"] for e in all_three["effects"]["kept"]]
    expect(kept == ["symplectic_euler", "drag", "soft_exp"], f"kept {kept}")
    opened = all_three["effects"]["modules_opened"]
    expect(opened == ["stdlib/integrate/symplectic_euler.part", "stdlib/force/drag.part",
                      "stdlib/pair/soft_exp.part"], f"opened {opened}")
    expect({"set": "P", "var": "f"} == {k: all_three["fused"][0][k] for k in ("set", "var")},
           f"fused {all_three['fused']}")
    kick = [s for s in all_three["statements"] if s["target"] == "v[i]"]
    expect(len(kick) == 1, f"statements for v: {kick}")
    effects = [o["effect"] for o in kick[0]["origins"]]
    expect(effects == ["drag", "soft_exp", "symplectic_euler"], f"origins of the kick {effects}")
    sums = kick[0]["accumulations"]
    expect(len(sums) == 1 and sums[0]["neighbours"] and sums[0]["newton"], f"sums {sums}")
    energy = [d for d in all_three["effects"]["liveness"] if d["what"] == "observable e_soft_exp"]
    expect(energy and not energy[0]["kept"], f"liveness of the energy {energy}")

    without = facts(partc, scene, "--drop", "drag")
    expect([e["name"] for e in without["effects"]["kept"]] == ["symplectic_euler", "soft_exp"],
           "kept with --drop drag")
    expect(without["effects"]["dropped"] == ["drag"], "dropped with --drop drag")
    expect("stdlib/force/drag.part" not in without["effects"]["modules_opened"],
           "a dropped effect's module was opened")

    # const gamma = 0 at the use line: drag's term is folded away, not computed.
    with tempfile.TemporaryDirectory() as folder:
        text = Path(scene).read_text()
        use = next(line for line in text.splitlines() if line.startswith("use force.drag"))
        folded_scene = Path(folder) / "folded.part"
        folded_scene.write_text(text.replace(use, "use force.drag(const gamma = 0) on P"))
        folded = facts(partc, str(folded_scene))
    terms = [(t["effect"], t["target"]) for t in folded["folded"]]
    expect(terms == [("drag", "P.f")], f"folded {terms}")
    kick = [s for s in folded["statements"] if s["target"] == "v[i]"]
    effects = [o["effect"] for o in kick[0]["origins"]]
    expect(effects == ["soft_exp", "symplectic_euler"], f"origins of the folded kick {effects}")
    expect(all_three["folded"] == [], "folded without a const 0")
    # One statement walks: nothing to fuse, nothing refused.
    expect(all_three["fused_passes"] == [] and all_three["not_fused_passes"] == [],
           f"passes of one walk {all_three['fused_passes']} {all_three['not_fused_passes']}")

    # LJ's energy, the force and Coulomb's energy: one pass of three statements.
    passes = facts(partc, fused_scene)["fused_passes"]
    expect(len(passes) == 1 and len(passes[0]["lines"]) == 3, f"fused passes {passes}")
    expect("one walk of search 1" in passes[0]["reason"], f"reason {passes[0]['reason']}")

    # Each step statement of an observable says whether it runs only on observed
    # steps, and why; so does a variable statement that does.
    runs = {s["target"]: s["runs"] for s in facts(partc, observed_scene)["statements"]
            if s["stage"] == "step" and "runs" in s}
    observed_only = sorted(t for t, r in runs.items() if r["observed_only"])
    expect(observed_only == ["e_pair", "e_tot", "u[i]"], f"observed only: {observed_only}")
    expect(sorted(runs) == ["e_kin", "e_pair", "e_tot", "n_hot", "u[i]"], f"runs of {sorted(runs)}")
    expect("line 26 reads it every step" in runs["e_kin"]["reason"], f"e_kin: {runs['e_kin']}")
    expect("adds to it (+=)" in runs["n_hot"]["reason"], f"n_hot: {runs['n_hot']}")
    print("--explain=json: effects, modules, fusion, origins, liveness, --drop, folding and "
          "observed steps and fused passes as expected")


if __name__ == "__main__":
    main()
