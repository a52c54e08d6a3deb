#!/usr/bin/env bash
# (Run at e33e1a0, reverted by 06e9264; SMLT built at e33e1a0, OLD at a022f10.)
# auto with the chains over the path tracer's estimate (`path-naive`) as a third candidate,
# weighed only where the path tracer's pilot met no fireflies, against the previous commit's
# auto (two candidates, `pt` and `naive`), on the auto bench's seven views: ../both_autos.sh,
# whose description says how to run it (the run went through the views in the order sunblind,
# atrium1, sibenik, slit, banner2, atrium2, sponza). Table: ../both_autos_table.py.
set -euo pipefail
HERE=$(dirname "$(readlink -f "$0")")
"$HERE/../both_autos.sh" "$HERE" bench old
