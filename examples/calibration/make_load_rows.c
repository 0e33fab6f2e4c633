/* Writes examples/calibration/load_rows.csv: rows of (pressures, rest pose) of the load level
 * of examples/calibration/load_supine_cap.yaml with a carried mass of 3.0 kg (the scene says 0.8 · 4.5 kg),
 * the poses measured with seeded normal noise of 0.05 mm and 0.05 degrees. Pressures come in
 * left/right pairs, the base's near 5 kPa and the sides' near 1.5 kPa (±2 %): the forward
 * statics find a rest reliably only for nearly symmetric pressures on this scene, and every
 * set kept also has one 60 g either side of the truth (docs/calibration.md).
 * Build and run from the source folder, against a built tree:
 *   cc -std=c11 -Iinclude -Ibuild/include examples/calibration/make_load_rows.c \
 *      -Lbuild -lheadplan -lstdc++ -lm -o /tmp/make_load_rows
 *   LD_LIBRARY_PATH=build /tmp/make_load_rows > examples/calibration/load_rows.csv */
#include "headplan/headplan.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#define MASS 3.0
#define ROWS 18

static uint64_t state = 20261201;

static double uniform(void) /* splitmix64, as the tests' generator */
{
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

static double normal(void)
{
    double u = uniform(), v = uniform();
    if (u < 1e-300) u = 1e-300;
    return sqrt(-2.0 * log(u)) * cos(2.0 * 3.14159265358979323846 * v);
}

int main(void)
{
    static hp_scene sc;
    hp_diag d = {{0}};
    if (hp_scene_load("examples/calibration/load_supine_cap.yaml", &sc, &d)) {
        fprintf(stderr, "%s\n", d.text);
        return 1;
    }
    hp_load_model *M[3];
    for (int q = 0; q < 3; ++q) {
        hp_load_spec s = sc.load;
        s.mass = MASS + (q == 0 ? 0.0 : q == 1 ? -0.06 : 0.06);
        if (hp_load_model_create(&sc.layout, &s, sc.load_geometry, &M[q], &d)) {
            fprintf(stderr, "%s\n", d.text);
            return 1;
        }
    }
    printf("# layout rows of the load level for examples/calibration/load_supine_cap.yaml "
           "(make_load_rows.c)\n"
           "# truth: carried_mass_kg=%g (offsets 0, semi-axes as the scene's)\n"
           "# pose noise sigma 0.05 mm, 0.05 deg\n",
           MASS);
    for (int k = 0; k < sc.layout.n; ++k) printf("p_%s_pa,", sc.layout.bladders[k].name);
    printf("x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n");
    for (int i = 0; i < ROWS;) {
        double P[HP_MAX_BLADDERS], xi[6], other[6];
        for (int k = 0; k < sc.layout.n; k += 2)
            P[k] = P[k + 1] = (k < 4 ? 5000.0 : 1500.0) * (1.0 + 0.02 * (2.0 * uniform() - 1.0));
        if (hp_load_rest(M[0], P, NULL, xi, NULL) || hp_load_rest(M[1], P, NULL, other, NULL) ||
            hp_load_rest(M[2], P, NULL, other, NULL))
            continue;
        for (int k = 0; k < sc.layout.n; ++k) printf("%.3f,", P[k]);
        for (int j = 0; j < 6; ++j)
            printf("%.5f%s",
                   (j < 3 ? xi[j] * 1e3 : xi[j] * 180.0 / 3.14159265358979323846) + 0.05 * normal(),
                   j < 5 ? "," : "\n");
        ++i;
    }
    for (int q = 0; q < 3; ++q) hp_load_model_destroy(M[q]);
    return 0;
}
