#!/bin/sh
# Mean CIELAB ΔE on the object of relief's 16- and 256-colour output and of
# chafa's, against relief's full-colour frame, at 160×96 pixels (160×48 cells).
# usage: docs/tools/colour_vs_chafa.sh path/to/relief   (needs chafa, python3 with numpy and Pillow)
R=$1
T=$(dirname "$0")/ansi_delta_e.py
set -e
frame() {
  name=$1; shift
  $R render --width 160 --height 96 "$@" --out $name.png
  bg=16,24,32; [ "$name" = plasma ] && bg=none
  for d in 16 256; do
    $R render --width 160 --height 96 "$@" --ansi --color $d > $name.r$d.ans
    $R render --width 160 --height 96 "$@" --ansi --color $d --dither > $name.r${d}d.ans
    chafa -f symbols -c $d -p off --symbols vhalf --size 160x48 --stretch $name.png > $name.c$d.ans
    for f in r$d r${d}d c$d; do
      printf "%-7s %-6s" $name $f; python3 $T $name.png $name.$f.ans $bg | cut -d: -f2
    done
  done
}
frame cube
frame sphere --model sphere
frame white --texture off --colors off
frame shadow --scene shadow
frame plasma --scene plasma
