/* JSON values the subcommands' --json outputs share (jansson). */
#ifndef CLI_JSON_OUT_H
#define CLI_JSON_OUT_H

#include "cli/cli_fidelity.h"

#include <jansson.h>

/* A pose [m, rad] as an object of the clinical keys (x_mm ... yaw_deg). */
json_t *cli_json_pose(const double xi[6]);

/* v[0..n) times scale as an array (e.g. metres to millimetres: scale 1e3). */
json_t *cli_json_vec(const double *v, int n, double scale);

/* v, or null when it is not finite: JSON has no infinity (an unbounded compliance). */
json_t *cli_json_num(double v);

/* An answer's model error (cli_fidelity.h) as the object solve --json prints under
 * "model_error": its keys in docs/kinematics.md. */
json_t *cli_json_model_error(const cli_model_error *e);

#endif
