#!/usr/bin/env bash
# Installs what cfrd needs and is missing: Debian packages ($1) and PyPI packages ($2).
# Checking is cheap (files and dpkg status only), so a second call returns at once.
set -euo pipefail
apt_packages=$1
pip_packages=$2

missing_apt=()
for pkg in $apt_packages; do
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    [[ $status == "install ok installed" ]] || missing_apt+=("$pkg")
done
if ((${#missing_apt[@]})); then
    echo "cfrd: installing Debian packages: ${missing_apt[*]}"
    sudo=""
    [[ $(id -u) -eq 0 ]] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        "${missing_apt[@]}" >/dev/null
fi

missing_pip=()
for pkg in $pip_packages; do
    case $pkg in
        fpm) command -v fpm >/dev/null 2>&1 || missing_pip+=("$pkg") ;;
        *) python3 -c "import importlib.util, sys; sys.exit(importlib.util.find_spec('$pkg') is None)" \
               2>/dev/null || missing_pip+=("$pkg") ;;
    esac
done
if ((${#missing_pip[@]})); then
    echo "cfrd: installing PyPI packages: ${missing_pip[*]}"
    python3 -m pip install -q --disable-pip-version-check "${missing_pip[@]}"
fi
