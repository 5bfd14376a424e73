# (b) macroscopic details: facade_rich.grammar at street level
# run from the repository root; the figure composites ground (paper_figs/facade_city.py)
pgt facade --city 25 --grammar grammars/facade_rich.grammar --seed 1 --camera 66,1.7,25,20,15,32,0,1,0,60 --light 80,45,70 --shadows --width 2560 --height 1440 -o fig1b.exr --png paper_figs/out/facade_fig1b.pgt.png --save-scene fig1b.scene
# camera: --camera 66,1.7,25,20,15,32,0,1,0,60
# scene: 25 buildings, 100 facades (28 visible), generated 1 ms
# frame: 2560x1440 = 3686400 pixels, 2 threads, 855.635 ms per frame (coverage 0.953 ms, rays 854.681 ms), 4.31 Mrays/s
# development: 2937832 rays entered a facade volume, 13.34 nodes developed per ray, 1.60 terminal tests, 14.00 rectangle tests; 3312129 pixel-facade pairs covered
# memory: procedural 6559 bytes (buildings, footprints, params, grammars), facades array 9200 bytes apart
