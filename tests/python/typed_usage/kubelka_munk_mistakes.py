"""A user's script with the Kubelka–Munk mistakes mypy must catch (test_typing.py counts them);
never run."""

import numpy as np

from metamer import kubelka_munk as km

bands = np.linspace(0.0, 1.0, 5)
km.reflectance("1", 10.0, 0.1)  # MISTAKE: K is a number, not a str
km.reflectance(1.0, 10.0, 0.1, substrat=0.8)  # MISTAKE: no keyword 'substrat'
r: float = km.reflectance(bands, 10.0, 0.1)  # MISTAKE: an array in, an array out
km.mix([(0.1, 2.0)])  # MISTAKE: (concentration, k, s)
km.stack([(1.0, 10.0, 0.1)], substrate=None)  # MISTAKE: a substrate reflectance, not None
n: int = km.k1(1.5)  # MISTAKE: a float
