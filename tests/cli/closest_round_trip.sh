# A CLOSEST answer the strict round trip does not confirm is refused (invalid-input, the safe
# output). Every path that plans such a row must say so the way solve does. Each case here was
# once answered otherwise (see the commit).
source "$2/tests/cli_lib.sh"
S=$(patient_scenes) || exit 1 # time budgets of 60 s (tests/cli_lib.sh)
H='# headplan-trace: rows=correction\nt_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n'
# An 89.9 deg pitch of the default scene: solve refuses it (65).
printf "$H"'0,1,0,0,0,0,0\n1,0,0,0,89.9,0,0\n2,1,0,0,0,0,0\n3,0,0,0,20,0,0\n' > "$TMP/t.csv"
run solve "$S/default.yaml" --correction 0,0,0,89.9,0,0
expect_exit 65 "solve, a closest pose the round trip refutes"
want="its closest reachable pose lies outside the identifiable range"
expect_stderr_has "$want" "solve names the refusal"
# horizon greedy and receding exited 70 ('1 of 4 rows failed') for the refused row where solve
# and batch exit 65; the outputs are still written with the row's status.
for m in greedy receding; do
    run horizon "$S/default.yaml" "$TMP/t.csv" --mode $m -o "$TMP/h.csv"
    expect_exit 65 "horizon --mode $m, a refused row"
    expect_stderr_has "$m: 1 of 4 rows refused (first $TMP/t.csv:4: invalid-input: desired: " "horizon --mode $m names it"
    grep -q "^$m,1,.*,invalid-input," "$TMP/h.csv" && ok || bad "horizon --mode $m -o states the row's status"
done
run batch "$S/default.yaml" "$TMP/t.csv" --format csv --no-times
expect_exit 65 "batch, a refused row"
expect_stderr_has "t.csv:4: desired: $want" "batch names the refusal"
# batch explained a refused row by planning it again on the planner's state at the end of
# the block, not the row's own: with rate limits the refusal depends on the previous
# pressures, and the row that the end state would plan as closest was reported as 'invalid
# correction'. Every refused row's reason must be the planner's, the same for any --jobs.
sed 's/^  stretch_max: 1.3$/  stretch_max: 1.3\n  rate_max_kpa: 2/; s#traces/drift_10hz.csv#'"$S"'/traces/drift_10hz.csv#' \
    "$S/default.yaml" > "$TMP/rate.yaml"
grep -q "rate_max_kpa: 2" "$TMP/rate.yaml" && ok || bad "the rate-limited scene was not made"
{ printf "$H"; for i in $(seq 0 39); do echo "$i,0,0,0,89.9,0,0"; done
  for i in $(seq 40 79); do echo "$i,0,0,0,0,0,0"; done; } > "$TMP/r.csv"
for j in 1 3; do
    run batch "$TMP/rate.yaml" "$TMP/r.csv" --format csv --no-times --jobs $j
    expect_exit 65 "batch --jobs $j, refused rows under rate limits"
    n=$(grep -c "r.csv:[0-9]*: desired: $want" "$TMP/err")
    inv=$(grep -c ',invalid-input,' "$TMP/out")
    [ "$inv" -gt 0 ] && [ "$n" -eq "$inv" ] && ok || bad "batch --jobs $j: $n reasons for $inv refused rows"
    grep -q "invalid correction" "$TMP/err" && bad "batch --jobs $j: a reason lost" || ok
    grep "r.csv:" "$TMP/err" > "$TMP/reasons$j"
done
cmp -s "$TMP/reasons1" "$TMP/reasons3" && ok || bad "batch: the reasons differ with --jobs"
finish
