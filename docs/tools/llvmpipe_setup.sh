#!/bin/sh
# Installs what docs/tools/llvmpipe_mesh.py needs: Mesa's EGL and llvmpipe
# (Debian packages) and a Python venv with PyOpenGL, numpy and pypng, by default in
# target/llvmpipe-venv (ignored by git). Usage: docs/tools/llvmpipe_setup.sh [VENV]
set -e
cd "$(dirname "$0")/../.."
venv=${1:-target/llvmpipe-venv}
if ! ldconfig -p | grep -q 'libEGL_mesa.so'; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update && apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1 python3-venv
  else
    echo "Mesa's EGL is missing: apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1" >&2
    exit 1
  fi
fi
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet 'PyOpenGL==3.1.10' 'numpy>=1.24' 'pypng>=0.20220715'
"$venv/bin/python" -c 'import OpenGL, numpy; print("PyOpenGL", OpenGL.__version__, "numpy", numpy.__version__)'
echo "ready: $venv/bin/python docs/tools/llvmpipe_mesh.py --help"
