#!/usr/bin/env bash
# expect_error.sh REGEX -- COMMAND ARGS...
# Passes when COMMAND exits with 2, prints no crash trace, and its first
# stderr line is one "softshadows: error: ..." line matching REGEX.
regex="$1"; shift
[ "$1" = "--" ] && shift
err=$(mktemp)
"$@" >/dev/null 2>"$err"
rc=$?
first=$(head -n1 "$err")
echo "exit code: $rc"
echo "first stderr line: $first"
status=0
if [ "$rc" -ne 2 ]; then echo "FAIL: expected exit code 2"; status=1; fi
if ! printf '%s\n' "$first" | grep -qE '^softshadows: error: '; then echo "FAIL: not a one-line error"; status=1; fi
if ! printf '%s\n' "$first" | grep -qE -- "$regex"; then echo "FAIL: message does not match: $regex"; status=1; fi
if grep -qiE 'segmentation|core dumped|terminate called|Aborted' "$err"; then echo "FAIL: crash"; status=1; fi
rm -f "$err"
exit $status
