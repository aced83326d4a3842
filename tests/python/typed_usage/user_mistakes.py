"""A user's script with the mistakes mypy must catch (test_typing.py counts them); never run."""

import metamer

r = metamer.render("scenes/spheres.json", backend="gpux")  # MISTAKE: not a backend
r = metamer.render("scenes/spheres.json", bits=12)  # MISTAKE: 8 or 16
print(r.cube.shape)  # MISTAKE: cube is None unless write kept it
name: str = r.width  # MISTAKE: an int
metamer.render("scenes/spheres.json", readback="fast")  # MISTAKE: auto, map or copy
