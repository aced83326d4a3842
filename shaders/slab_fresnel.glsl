// A plane-parallel slab's transmittance T and reflectance R for 4 bands at cos θ = cosI, index n
// and attenuation a·d·log2(10) across it: Fresnel at both faces, the glass's absorption along the
// refracted path, the reflections inside summed incoherently, s and p averaged —
// spectral/dielectric.cpp's slab(), in float. One formula for the transmission and slab
// reflection passes (transmit.frag) and the response pass and coloured shadows (spectral.frag),
// so that their products agree to rounding. Physics: docs/physics.md, "Transparent objects".
void slabFresnel(float cosI, vec4 n, vec4 attenuation, out vec4 T, out vec4 R) {
    const vec4 cosT = sqrt(max(vec4(1.0) - (1.0 - cosI * cosI) / (n * n), vec4(0.0)));
    const vec4 tau = exp2(-attenuation / max(cosT, vec4(1e-6)));
    vec4 rs = (cosI - n * cosT) / (cosI + n * cosT), rp = (cosT - n * cosI) / (cosT + n * cosI);
    rs *= rs;
    rp *= rp;
    const vec4 ds = 1.0 / (1.0 - rs * rs * tau * tau), dp = 1.0 / (1.0 - rp * rp * tau * tau);
    T = 0.5 * ((1.0 - rs) * (1.0 - rs) * tau * ds + (1.0 - rp) * (1.0 - rp) * tau * dp);
    R = 0.5 * (rs + (1.0 - rs) * (1.0 - rs) * rs * tau * tau * ds + rp + (1.0 - rp) * (1.0 - rp) * rp * tau * tau * dp);
}
