pgt facade --scene paper_figs/scenes/facade_one.scene --camera 3,4.5,19,12,5.5,12,0,1,0,45 --light -40,30,40 --shadows --detail geometry --width 960 --height 600 -o paper_figs/out/facade_lod_geometry.exr --png paper_figs/out/facade_lod_geometry.png
camera: --camera 3,4.5,19,12,5.5,12,0,1,0,45
scene: 1 buildings, 4 facades (3 visible), read 0 ms
frame: 960x600 = 576000 pixels, 2 threads, 95.248 ms per frame (coverage 0.045 ms, rays 95.202 ms), 6.05 Mrays/s
development: 432113 rays entered a facade volume, 8.04 nodes developed per ray, 1.16 terminal tests, 15.89 rectangle tests; 437547 pixel-facade pairs covered
memory: procedural 2375 bytes (buildings, footprints, params, grammars), facades array 368 bytes apart
