# Second round of seams: the same request reaching the program by another path (an option
# given twice, two outputs naming one file, a byte-order mark, a result cut short) must get
# the same honest answer. Each case here was once answered wrongly (see the commit).
source "$2/tests/cli_lib.sh"
S="$HP_SRC/scenarios"
E="$HP_SRC/examples/calibration"

# fit material took the last of two --Ri-mm (--Ro-mm, --plot, --fit-ref) silently, exit 0;
# every other subcommand, fit layout included, refuses an option given twice.
for o in "--Ri-mm 28" "--Ro-mm 31" "--fit-ref Ri --fit-ref Ro" "--plot $TMP/a.svg --plot $TMP/b.svg"; do
    run fit material "$E/material_ri.csv" --Ri-mm 27 --Ro-mm 30 $o
    expect_exit 64 "fit material $o"; expect_stderr_has "given more than once" "fit material $o"
    expect_stdout_empty "fit material $o"
done
finish
