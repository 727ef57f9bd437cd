#!/usr/bin/env python3
"""Within a slot, the statement merging every contribution to a channel
runs after each contributor's earlier statements: in scene_ordering.part,
two_step's w is set before the f it feeds (so both fuse into the kick).

    check_ordering.py PARTC SCENE
"""
import json
import subprocess
import sys

partc, scene = sys.argv[1], sys.argv[2]
facts = json.loads(subprocess.run([partc, scene, "--explain=json"], check=True,
                                  capture_output=True, text=True).stdout)
order = [s["target"] for s in facts["statements"] if s["stage"] == "step"]
fused = sorted(f["var"] for f in facts["fused"])
print("step statements:", order, "fused:", fused)
if fused != ["f", "two_step_w"] or order != ["v[i]", "p[i]"]:
    sys.exit("w must be set before the merged f reads it (both then fuse into the kick)")
