#!/usr/bin/env bash
# Debian packages the project needs: libusb-1.0-0 (imported by open3d), chromium and
# chromium-driver (the browser test of the built book, tests/test_book_browser.py).
# Installs only what is missing, and only when running as root; otherwise says what to install.
set -euo pipefail
needed=(libusb-1.0-0 chromium chromium-driver)
missing=()
for pkg in "${needed[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
  echo "installing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >/dev/null
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "warning: missing Debian packages ${missing[*]}; install them with: sudo apt-get install ${missing[*]}" >&2
fi
