"""The camera and what moves it: transforms, the orbit, the controls, frame times and slow frames."""
