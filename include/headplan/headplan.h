/* headplan: a desired 6-DOF head correction -> the pressures of an eight-bladder soft robot.
 * The one header a user includes. */
#ifndef HEADPLAN_H
#define HEADPLAN_H

#include "headplan/hp_version.h"
#include "headplan/hp_common.h"
#include "headplan/hp_iab.h"
#include "headplan/hp_pose.h"
#include "headplan/hp_layout.h"
#include "headplan/hp_contact.h"
#include "headplan/hp_load.h"
#include "headplan/hp_scene.h"
#include "headplan/hp_trace.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_horizon.h"
#include "headplan/hp_trace_plan.h"
#include "headplan/hp_trace_columns.h"
#include "headplan/hp_calib.h"

#endif
