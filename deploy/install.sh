#!/usr/bin/env bash
# Installs a Release build as a system service (run as root after deploy/build.sh release):
# binaries to /usr/local/bin, the Python package to /usr/local/lib/python3.11/dist-packages/ispars,
# scenes to /usr/local/share/ispars/scenes, the config and Fast DDS
# profiles to /etc/ispars (kept when already there), the systemd unit, and an `ispars` user.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/bin/isparsd ] || { echo "install.sh: build first (deploy/build.sh release)" >&2; exit 2; }
cmake --install build --prefix /usr/local
install -d /etc/ispars
for f in isparsd.yaml fastdds_localhost.xml fastdds_fleet.xml; do
  [ -e "/etc/ispars/$f" ] || install -m 0644 "deploy/$f" "/etc/ispars/$f"
done
id ispars >/dev/null 2>&1 || useradd --system --home /var/lib/ispars --shell /usr/sbin/nologin ispars
install -d -o ispars -g ispars -m 0750 /var/lib/ispars
install -m 0644 deploy/isparsd.service /etc/systemd/system/isparsd.service
if command -v systemctl >/dev/null 2>&1 && [ -d /run/systemd/system ]; then
  systemctl daemon-reload
  echo "install.sh: installed; start with: systemctl enable --now isparsd"
else
  echo "install.sh: installed (no systemd running here; start /usr/local/bin/isparsd --config /etc/ispars/isparsd.yaml)"
fi
