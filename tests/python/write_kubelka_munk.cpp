// Writes Kubelka–Munk layers as engine/spectral/kubelka_munk computes them, for
// tests/python/check_kubelka_munk.py to compare with its numpy closed forms and scipy's solve of
// the two-flux equations: one line per case — K, S, X, Rg, R (over Rg), R over black, T, R∞, and
// Saunderson's measured reflectance of R∞ with k1 = 0.04, k2 = 0.6; then one line per refractive
// index with k1 and the internal and external diffuse reflectances (integrated Fresnel).
// Usage: write_kubelka_munk PREFIX (writes PREFIX_layers.csv and PREFIX_interfaces.csv)
#include "spectral/kubelka_munk.h"

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    using namespace metamer;
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s PREFIX\n", argv[0]);
        return 2;
    }
    const std::string layers = std::string(argv[1]) + "_layers.csv", interfaces = std::string(argv[1]) + "_interfaces.csv";
    std::FILE* f = std::fopen(layers.c_str(), "w");
    if (!f) {
        std::perror(layers.c_str());
        return 1;
    }
    std::fprintf(f, "K,S,X,Rg,R,R_black,T,R_inf,R_saunderson\n");
    for (double K : {0.0, 0.05, 1.0, 8.0})
        for (double S : {0.1, 1.0, 10.0, 60.0})
            for (double X : {0.001, 0.02, 0.1, 0.5, 3.0})
                for (double Rg : {0.0, 0.05, 0.8, 1.0}) {
                    const KubelkaMunkLayer l = kubelkaMunkLayer(K, S, X);
                    const double rInf = kubelkaMunkInfinite(K, S);
                    std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", K, S, X, Rg,
                                 kubelkaMunkOverSubstrate(K, S, X, Rg), l.reflectance, l.transmittance, rInf,
                                 saundersonMeasured(rInf, 0.04, 0.6));
                }
    if (std::fclose(f) != 0) return 1;
    std::FILE* g = std::fopen(interfaces.c_str(), "w");
    if (!g) {
        std::perror(interfaces.c_str());
        return 1;
    }
    std::fprintf(g, "n,k1,internal,external\n");
    for (double n : {1.0, 1.2, 1.33, 1.4, 1.5, 1.6, 1.8, 2.0, 2.4, 3.0})
        std::fprintf(g, "%.17g,%.17g,%.17g,%.17g\n", n, saundersonK1(n), internalDiffuseReflectance(n),
                     externalDiffuseReflectance(n));
    return std::fclose(g) == 0 ? 0 : 1;
}
