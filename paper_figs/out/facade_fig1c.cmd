# (c) the paper's grammar (sec. 3) on one building, frontal
# run from the repository root; the figure composites ground (paper_figs/facade_city.py)
pgt facade --scene paper_figs/scenes/facade_one.scene --camera 11,9.6,42,11,9.6,12,0,1,0,40 --light -30,40,30 --shadows --width 2560 --height 1440 -o fig1c.exr --png paper_figs/out/facade_fig1c.pgt.png
# camera: --camera 11,9.6,42,11,9.6,12,0,1,0,40
# scene: 1 buildings, 4 facades (4 visible), read 1 ms
# frame: 2560x1440 = 3686400 pixels, 2 threads, 726.893 ms per frame (coverage 0.142 ms, rays 726.751 ms), 5.07 Mrays/s
# development: 1970382 rays entered a facade volume, 7.38 nodes developed per ray, 1.01 terminal tests, 13.50 rectangle tests; 2233654 pixel-facade pairs covered
# memory: procedural 2375 bytes (buildings, footprints, params, grammars), facades array 368 bytes apart
