"""Files in and out: input checks, atomic writes, output folders that own only what they wrote, verified cache
entries, image and video IO, the bundled assets, the bandwidth record, the process's runtime folder."""
