# (a) 10K facades: --city 2500, paper grammar, self-shadowing
# run from the repository root; the figure composites ground (paper_figs/facade_city.py)
pgt facade --city 2500 --grammar grammars/facade.grammar --seed 1 --camera -120,260,-120,500,0,500,0,1,0,50 --light -1000,1400,-500 --shadows --width 2560 --height 1440 -o fig1a.exr --png paper_figs/out/facade_fig1a.pgt.png --save-scene fig1a.scene
# camera: --camera -120,260,-120,500,0,500,0,1,0,50
# scene: 2500 buildings, 10000 facades (9956 visible), generated 9 ms
# frame: 2560x1440 = 3686400 pixels, 2 threads, 450.399 ms per frame (coverage 3.468 ms, rays 446.931 ms), 8.18 Mrays/s
# development: 1394773 rays entered a facade volume, 7.42 nodes developed per ray, 1.16 terminal tests, 15.58 rectangle tests; 2308732 pixel-facade pairs covered
# memory: procedural 212267 bytes (buildings, footprints, params, grammars), facades array 920000 bytes apart
