"""Fresnel's equations and their integral over a Lambertian hemisphere, by scipy's quadrature: the
independent oracle for the engine's diffuse interface reflectances (Saunderson's k2, the external
r_e; spectral/kubelka_munk), shared by check_kubelka_munk.py and test_kubelka_munk.py."""
import math

from scipy.integrate import quad


def fresnel_unpolarized(n1, n2, cos_i):
    """Fresnel's reflectance from index n1 into n2 at incidence cos_i, unpolarized; 1 beyond the
    critical angle."""
    sin_t = n1 / n2 * math.sqrt(max(0.0, 1.0 - cos_i * cos_i))
    if sin_t >= 1.0:
        return 1.0
    cos_t = math.sqrt(1.0 - sin_t * sin_t)
    rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t)
    rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t)
    return 0.5 * (rs * rs + rp * rp)


def diffuse_reflectance(n1, n2):
    """∫ R(θ)·2 sin θ cos θ dθ over the hemisphere, from n1 into n2, by adaptive quadrature in θ
    (the critical angle as a break point)."""
    critical = [math.asin(n2 / n1)] if n1 > n2 else None
    f = lambda t: fresnel_unpolarized(n1, n2, math.cos(t)) * 2.0 * math.sin(t) * math.cos(t)
    return quad(f, 0.0, math.pi / 2, points=critical, epsabs=1e-14, epsrel=1e-13, limit=200)[0]
