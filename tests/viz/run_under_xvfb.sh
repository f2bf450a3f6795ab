#!/bin/sh
# xvfb-run -a, returning only once its X server has exited. xvfb-run signals Xvfb and exits
# without waiting; the dying server then competes with whatever ctest starts next (the 500 Hz
# real-time test measured 13-23 deadline misses in 1500 ticks right after it, 0-2 otherwise).
# usage: run_under_xvfb.sh XVFB_RUN SERVER_ARGS COMMAND...
xvfb_servers() {
  for p in /proc/[0-9]*; do
    [ "$(cat "$p/comm" 2>/dev/null)" = Xvfb ] && echo "${p#/proc/}"
  done
}
xvfb_run=$1 server_args=$2
shift 2
before=" $(xvfb_servers | tr '\n' ' ') "
"$xvfb_run" -a -s "$server_args" "$@"
rc=$?
tries=0
while [ $tries -lt 100 ]; do  # up to 10 s
  left=0
  for pid in $(xvfb_servers); do
    case "$before" in *" $pid "*) ;; *) left=1 ;; esac
  done
  [ $left -eq 0 ] && break
  sleep 0.1
  tries=$((tries + 1))
done
exit $rc
