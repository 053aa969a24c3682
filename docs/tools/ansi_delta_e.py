#!/usr/bin/env python3
"""Decode half-block ANSI text back to pixels and compare it with a picture.

usage: ansi_delta_e.py FULL.png TEXT.ans [BACKGROUND r,g,b or "none"]
Prints mean CIELAB ΔE76 over the object (pixels of FULL that are not the
background), PSNR over the whole frame, and the share of neutral object pixels
shown saturated. Palette colours decode to xterm's default values.
"""
import re, sys
import numpy as np
from PIL import Image

ANSI16 = [(0,0,0),(205,0,0),(0,205,0),(205,205,0),(0,0,238),(205,0,205),(0,205,205),(229,229,229),
          (127,127,127),(255,0,0),(0,255,0),(255,255,0),(92,92,255),(255,0,255),(0,255,255),(255,255,255)]
CUBE = [0,95,135,175,215,255]

def idx(n):
    if n < 16: return ANSI16[n]
    if n < 232:
        n -= 16; return (CUBE[n//36], CUBE[n//6%6], CUBE[n%6])
    g = 8 + 10*(n-232); return (g,g,g)

def decode(text, w, h, default_fg=(229,229,229), default_bg=(0,0,0)):
    out = np.zeros((h, w, 3), np.uint8)
    fg, bg, inv = default_fg, default_bg, False
    x = y = 0
    i = 0
    while i < len(text):
        c = text[i]
        if c == '\x1b':
            m = re.match(r'\x1b\[([0-9;?]*)([A-Za-z])', text[i:])
            i += m.end()
            if m.group(2) != 'm': continue
            ps = [int(p) if p else 0 for p in m.group(1).split(';')]
            k = 0
            while k < len(ps):
                p = ps[k]
                if p == 0: fg, bg, inv = default_fg, default_bg, False
                elif p == 7: inv = True
                elif p == 27: inv = False
                elif 30 <= p <= 37: fg = ANSI16[p-30]
                elif 90 <= p <= 97: fg = ANSI16[p-90+8]
                elif 40 <= p <= 47: bg = ANSI16[p-40]
                elif 100 <= p <= 107: bg = ANSI16[p-100+8]
                elif p == 39: fg = default_fg
                elif p == 49: bg = default_bg
                elif p in (38, 48):
                    if ps[k+1] == 5: col = idx(ps[k+2]); k += 2
                    else: col = tuple(ps[k+2:k+5]); k += 4
                    if p == 38: fg = col
                    else: bg = col
                k += 1
            continue
        i += 1
        if c == '\r': x = 0; continue
        if c == '\n': y += 1; x = 0; continue
        f, b = (bg, fg) if inv else (fg, bg)
        top, bot = {'▀': (f, b), '▄': (b, f), '█': (f, f), ' ': (b, b)}[c]
        if x < w and 2*y+1 < 2*h + 1 and y < h//2:
            out[2*y, x] = top; out[2*y+1, x] = bot
        x += 1
    return out

def srgb_to_lab(img):
    c = img.astype(np.float64) / 255
    lin = np.where(c <= 0.04045, c/12.92, ((c+0.055)/1.055)**2.4)
    M = np.array([[0.4124564,0.3575761,0.1804375],[0.2126729,0.7151522,0.0721750],[0.0193339,0.1191920,0.9503041]])
    xyz = lin @ M.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6/29)**3, np.cbrt(xyz), xyz/(3*(6/29)**2) + 4/29)
    L = 116*f[...,1] - 16; a = 500*(f[...,0]-f[...,1]); b = 200*(f[...,1]-f[...,2])
    return np.stack([L,a,b], -1)

def compare(full, shown, background):
    obj = np.ones(full.shape[:2], bool) if background is None else np.any(full != np.array(background, np.int32), -1)
    la, lb = srgb_to_lab(full), srgb_to_lab(shown)
    de = np.linalg.norm(la - lb, axis=-1)
    mse = np.mean((full.astype(float) - shown.astype(float))**2)
    psnr = 10*np.log10(255**2/mse)
    chroma_a = np.hypot(la[...,1], la[...,2]); chroma_b = np.hypot(lb[...,1], lb[...,2])
    neutral = obj & (chroma_a < 5)
    sat = neutral & (chroma_b > 20)
    return de[obj].mean(), psnr, sat.sum()/max(neutral.sum(),1), neutral.sum()/obj.sum()

if __name__ == '__main__':
    full = np.asarray(Image.open(sys.argv[1]).convert('RGB'))
    h, w, _ = full.shape
    bg = None if len(sys.argv) > 3 and sys.argv[3] == "none" else tuple(int(v) for v in sys.argv[3].split(",")) if len(sys.argv) > 3 else (16, 24, 32)
    for path in sys.argv[2:3]:
        shown = decode(open(path, encoding='utf-8').read(), w, h)
        de, psnr, sat, neu = compare(full, shown, bg)
        print(f"{path}: mean ΔE {de:.1f}  PSNR {psnr:.2f} dB  neutral→saturated {100*sat:.0f}% (of {100*neu:.0f}% neutral)")
