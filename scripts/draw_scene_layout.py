#!/usr/bin/env python3
"""Draws where the box to grasp and one obstacle stand in a new test room, from a seed, so a room
added to check the navigation on unseen layouts is not placed by hand (configs/scenes/garage.yaml
and studio.yaml: seeds 20261123 and 20261124; loft.yaml and atelier.yaml: 20261201 and 20261202,
which also drew the obstacle's kind, a draw added after the first two; gallery.yaml and
cellar.yaml: 20261203 and 20261204; pantry.yaml and foyer.yaml: 20261205 and 20261206;
scullery.yaml and vestibule.yaml: 20261207 and 20261208). Usage:
draw_scene_layout.py SEED"""
import math
import random
import sys

r = random.Random(int(sys.argv[1]))
d = r.uniform(1.6, 3.0)        # the box's distance from the start [m]
b = r.uniform(-30.0, 30.0)     # its bearing from the way ahead [deg]
yaw = r.uniform(0.0, 360.0)    # how it is turned [deg]
dims = [round(r.uniform(0.2, 0.34), 2) for _ in range(3)]  # [m]
bx, by = d * math.cos(math.radians(b)), d * math.sin(math.radians(b))
while True:  # the obstacle: 0.8 m to d + 0.5 m away within 40 deg, 0.6 m from box and start
    od, ob = r.uniform(0.8, d + 0.5), r.uniform(-40.0, 40.0)
    ox, oy = od * math.cos(math.radians(ob)), od * math.sin(math.radians(ob))
    if math.hypot(ox - bx, oy - by) > 0.6 and math.hypot(ox, oy) > 0.6:
        break
turn = r.uniform(0.0, 90.0)
# Its kind (drawn after the rest, so the layouts of the rooms drawn before it stand as they were):
# a table (0.9 x 0.6 m top at 0.74 m on four legs), a chair (0.45 m seat at 0.45 m, backrest), a
# closed shelf unit (0.4 x 0.8 x 1.0 m), a crate (0.32 x 0.28 x 0.40 m) or a pillar (0.25 m, to
# the ceiling).
kind = r.choice(["table", "chair", "shelf", "crate", "pillar"])
print(f"box at ({bx:.2f}, {by:.2f}) m, {d:.2f} m away, turned {yaw:.0f} deg, {dims} m; "
      f"obstacle ({kind}) at ({ox:.2f}, {oy:.2f}) m, turned {turn:.0f} deg")
