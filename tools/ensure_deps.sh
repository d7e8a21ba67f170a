#!/usr/bin/env bash
# Installs what cfrd needs and is missing: Debian packages ($1) and PyPI packages ($2).
# Checking asks dpkg once and Python once (no imports), so a second call returns at once.
set -euo pipefail
apt_packages=$1
pip_packages=$2

# dpkg-query prints one status line per known package; unknown ones go to stderr.
installed=$(dpkg-query -W -f='${Package} ${Status}\n' $apt_packages 2>/dev/null |
    awk '$NF == "installed" {print $1}' || true)
missing_apt=()
for pkg in $apt_packages; do
    grep -qx "$pkg" <<<"$installed" || missing_apt+=("$pkg")
done
if ((${#missing_apt[@]})); then
    echo "cfrd: installing Debian packages: ${missing_apt[*]}"
    sudo=""
    [[ $(id -u) -eq 0 ]] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        "${missing_apt[@]}" >/dev/null
fi

# fpm is a command; the others are Python modules (find_spec looks without importing).
missing_pip=$(python3 - $pip_packages <<'PY'
import importlib.util, shutil, sys
for name in sys.argv[1:]:
    found = shutil.which(name) if name == "fpm" else importlib.util.find_spec(name)
    if not found:
        print(name)
PY
)
if [[ -n $missing_pip ]]; then
    echo "cfrd: installing PyPI packages: $(echo $missing_pip)"
    python3 -m pip install -q --disable-pip-version-check $missing_pip
    hash -r
    if command -v pyenv >/dev/null 2>&1; then pyenv rehash; fi
fi
