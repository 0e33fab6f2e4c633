# Seams between calibration, scenes and the command line: each block states what the
# command did wrong and checks the behaviour it has now (exit status, one-line message).
source "$2/tests/cli_lib.sh"
HP_BIN=$(realpath "$HP_BIN"); HP_SRC=$(realpath "$HP_SRC")
S="$HP_SRC/scenarios"

# render draws the plan's message: a closest answer names its binding limits (the note),
# as solve prints them.
run render "$S/default.yaml" --correction 30,0,0,0,0,0 --dry-run
expect_exit 0 "render --dry-run of a closest plan"
expect_stdout_has "closest: binding side_fore_left pressure_min" "render shows the closest note"

finish
