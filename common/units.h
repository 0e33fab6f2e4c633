/* The one place for unit scaling: the library speaks SI (m, rad, Pa); files, the command
 * line and the solvers' scaled variables speak mm and degrees. Every conversion in the tree
 * uses these constants (none defines π or a factor of its own). */
#ifndef HP_COMMON_UNITS_H
#define HP_COMMON_UNITS_H

#define HP_PI 3.14159265358979323846
#define HP_MM_PER_M 1e3
#define HP_DEG_PER_RAD (180.0 / HP_PI)
#define HP_RAD_PER_DEG (HP_PI / 180.0)

#endif
