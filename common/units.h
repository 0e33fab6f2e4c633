/* The one place for unit scaling: the library speaks SI (m, rad, Pa); files, the command
 * line and the solvers' scaled variables speak mm and degrees. Every conversion in the tree
 * uses these constants (none defines π or a factor of its own). */
#ifndef HP_COMMON_UNITS_H
#define HP_COMMON_UNITS_H

#define HP_PI 3.14159265358979323846
#define HP_MM_PER_M 1e3
#define HP_DEG_PER_RAD (180.0 / HP_PI)
#define HP_RAD_PER_DEG (HP_PI / 180.0)

/* A pose [x, y, z (m), pitch, roll, yaw (rad)] component i in the solvers' scaled units
 * (mm, degrees) per SI unit, and its inverse: the scale every backend and the horizon
 * planner use for their variables. */
static inline double hpi_pose_scaled_per_si(int i) { return i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD; }
static inline double hpi_pose_si_per_scaled(int i)
{
    return i < 3 ? 1.0 / HP_MM_PER_M : HP_RAD_PER_DEG;
}

#endif
