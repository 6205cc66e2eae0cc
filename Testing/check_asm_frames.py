"""Checks that `softshadows render --method asm --frames N` is progressive and
says so: with more frames the same still view has more nodes and at least the
same effective resolution, within the memory budget, and the stats of the short
run report that it was still refining."""
import json
import sys

short, long_ = (json.load(open(p))["pass"]["asm"] for p in sys.argv[1:3])
failures = []
if not short["refining"]:
    failures.append("after 1 frame the still view should still be refining")
if not long_["nodes"] > short["nodes"]:
    failures.append("nodes %d after more frames, %d after 1" % (long_["nodes"], short["nodes"]))
if long_["effective_resolution"] < short["effective_resolution"]:
    failures.append("effective resolution fell: %d -> %d" % (short["effective_resolution"], long_["effective_resolution"]))
for s in (short, long_):
    if s["memory_used_bytes"] > s["memory_budget_bytes"]:
        failures.append("memory %d over the budget %d" % (s["memory_used_bytes"], s["memory_budget_bytes"]))
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("asm --frames: %d nodes after 1 frame (refining), %d after more (%s), effective resolution %d -> %d" % (
    short["nodes"], long_["nodes"], "refining" if long_["refining"] else "done",
    short["effective_resolution"], long_["effective_resolution"]))
