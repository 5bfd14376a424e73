pgt facade --scene paper_figs/scenes/facade_one.scene --camera 3,4.5,19,12,5.5,12,0,1,0,45 --light -40,30,40 --shadows --detail flat --width 960 --height 600 -o paper_figs/out/facade_lod_flat.exr --png paper_figs/out/facade_lod_flat.png
camera: --camera 3,4.5,19,12,5.5,12,0,1,0,45
scene: 1 buildings, 4 facades (3 visible), read 0 ms
frame: 960x600 = 576000 pixels, 2 threads, 57.144 ms per frame (coverage 0.058 ms, rays 57.086 ms), 10.08 Mrays/s
development: 421977 rays entered a facade volume, 7.63 nodes developed per ray, 1.00 terminal tests, 13.99 rectangle tests; 437966 pixel-facade pairs covered
memory: procedural 2375 bytes (buildings, footprints, params, grammars), facades array 368 bytes apart
