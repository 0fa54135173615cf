#!/usr/bin/env bash
# Every executable and subcommand answers --help; both executables answer --version.
source "$(dirname "$0")/lib.sh"
check_help() {
  local out
  if out=$("$@" --help 2>&1) && grep -q "Usage:" <<<"$out"; then pass "$* --help"; else fail "$* --help"; fi
}
check_help "$ROADCROSS_BUILD"
check_help "$ROADCROSS"
for sub in $("$ROADCROSS" --help | awk '/^Subcommands:/ {s=1; next} s && NF {print $1}'); do
  check_help "$ROADCROSS" "$sub"
done
"$ROADCROSS_BUILD" --version | grep -Eq '^roadcross-build [0-9]+\.[0-9]+\.[0-9]+' && pass "build --version" || fail "build --version"
"$ROADCROSS" --version | grep -Eq '^roadcross [0-9]+\.[0-9]+\.[0-9]+' && pass "roadcross --version" || fail "roadcross --version"
# The subcommand list is not empty (so the loop above tested something).
[[ $("$ROADCROSS" --help | awk '/^Subcommands:/ {s=1; next} s && NF' | wc -l) -ge 3 ]] || fail "fewer than 3 subcommands"
finish
