#!/bin/sh
# Install Debian's chromium for the browser test (tests/test_viewer.py) when it is missing.
#
# Source it (`. .ci/browser.sh`) or run it (`sh .ci/browser.sh`): it never fails the caller.
# Without apt-get, or without the rights to use it, it says so and the browser test skips with
# that reason. Needs network access to the Debian mirrors only when chromium is missing.

feeder_install_chromium() {
    if command -v chromium >/dev/null 2>&1; then
        return 0
    fi
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "browser.sh: no apt-get here; tests/test_viewer.py will skip its browser checks" >&2
        return 0
    fi
    if [ "$(id -u)" -eq 0 ]; then
        sudo_=""
    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        sudo_="sudo -n"
    else
        echo "browser.sh: not root and no password-less sudo: cannot install chromium" >&2
        return 0
    fi
    echo "browser.sh: installing chromium with apt-get (a minute or two)" >&2
    if $sudo_ apt-get update -q >/dev/null \
        && DEBIAN_FRONTEND=noninteractive $sudo_ apt-get install -y -q chromium >/dev/null; then
        echo "browser.sh: $(chromium --version 2>/dev/null)" >&2
    else
        echo "browser.sh: apt-get could not install chromium; the browser checks will skip" >&2
    fi
    return 0
}

feeder_install_chromium
