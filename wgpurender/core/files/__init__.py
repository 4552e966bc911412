"""Files in and out: input checks, atomic writes, image and video IO, the bundled assets, the bandwidth record."""
