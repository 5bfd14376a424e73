# (c) the paper's grammar (sec. 3) on one building, frontal
# run from the repository root; the figure composites ground (paper_figs/facade_city.py)
pgt facade --scene paper_figs/scenes/facade_one.scene --camera 11,9.6,42,11,9.6,12,0,1,0,40 --light -30,40,30 --shadows --width 1280 --height 720 -o fig1c.exr --png paper_figs/out/facade_fig1c.pgt.png
# camera: --camera 11,9.6,42,11,9.6,12,0,1,0,40
# scene: 1 buildings, 4 facades (4 visible), read 0 ms
# frame: 1280x720 = 921600 pixels, 2 threads, 181.297 ms per frame (coverage 0.065 ms, rays 181.233 ms), 5.08 Mrays/s
# development: 493364 rays entered a facade volume, 7.36 nodes developed per ray, 1.01 terminal tests, 13.49 rectangle tests; 559266 pixel-facade pairs covered
# memory: procedural 15407 bytes (buildings, footprints, params, grammars), facades array 368 bytes apart
