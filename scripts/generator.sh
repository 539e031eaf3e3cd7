# shellcheck shell=bash
# Sourced by the scripts that configure a build tree: Ninja when it is installed
# (install-deps.sh installs it). It schedules the whole tree's compiles as one graph and
# tells what is up to date faster than make does (issue 41, build time). A tree configured
# before keeps the generator it has; CMAKE_GENERATOR set by the caller wins.
if [ -z "${CMAKE_GENERATOR:-}" ] && command -v ninja >/dev/null; then
  export CMAKE_GENERATOR=Ninja
fi
