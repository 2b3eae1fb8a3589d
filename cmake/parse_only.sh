#!/bin/sh
# The compiler launcher of the header checks (IsparsHeaderCheck.cmake): runs the compile command
# it is given with -fsyntax-only (a header's check needs its parse, not code: half the time), then
# leaves the empty object file the build expects, so that an unchanged header is not parsed again.
out=""
previous=""
for arg in "$@"; do
  [ "$previous" = "-o" ] && out="$arg"
  previous="$arg"
done
"$@" -fsyntax-only || exit $?
[ -z "$out" ] || : > "$out"
