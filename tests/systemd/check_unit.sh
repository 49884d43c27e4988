#!/usr/bin/env bash
# Checks the systemd unit offline, as CI must (no systemd as PID 1 here):
# `systemd-analyze verify` must print nothing, the unit must restart for ever, and the
# exposure score must be <= 2.0.
# ExecStart is pointed at the freshly built daemon, since verify wants an existing file.
set -euo pipefail
unit_in=$1 daemon=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e "s|@CMAKE_INSTALL_FULL_DOCDIR@|/usr/share/doc/ccdlane|" \
    -e "s|@CCDLANED_PATH@|$daemon|" \
    -e "s|@CCDLANE_CONFIG_PATH@|/etc/ccdlane/ccdlane.toml|" "$unit_in" > "$work/ccdlane.service"

out=$(systemd-analyze verify --man=no "$work/ccdlane.service" 2>&1) || { echo "$out"; exit 1; }
if [[ -n "$out" ]]; then
  echo "systemd-analyze verify printed (any output is a failure):"
  echo "$out"
  exit 1
fi
echo "verify: clean"

# The service must never give up restarting (a camera away for longer than systemd's
# default burst of 5 starts in 10 s once left it failed for good).
for setting in "StartLimitIntervalSec=0" "Restart=on-failure"; do
  grep -qx "$setting" "$work/ccdlane.service" || { echo "the unit lacks $setting"; exit 1; }
done
echo "restarts: for ever"

systemd-analyze security --offline=true --threshold=20 "$work/ccdlane.service" > "$work/security.txt" 2>&1 || {
  cat "$work/security.txt"
  echo "exposure above 2.0"
  exit 1
}
grep "Overall exposure level" "$work/security.txt"
