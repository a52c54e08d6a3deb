#!/usr/bin/env bash
# (Run at 5f205fd; SMLT built at 5f205fd, OLD at a022f10.)
# auto keeping the chosen method's pilot where it rendered the render's pixels (128×72 here, so
# the pilot is at the render's size) against the previous commit's auto (the same choice, its
# pilot discarded), on the auto bench's seven views: ../both_autos.sh, whose description says
# how to run it; the showcase's two views: showcase.sh. Table: ../both_autos_table.py.
set -euo pipefail
HERE=$(dirname "$(readlink -f "$0")")
"$HERE/../both_autos.sh" "$HERE" kept kold
