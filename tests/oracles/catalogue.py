"""The car catalogue of the report *Minimization of parking slots for parallel parking*
(2022, after Vlasák, Sojka & Hanzálek), typed from its appendix: lotsim's built-in cars
must match it."""

# (width w, rear axle to front bumper df, rear axle to rear bumper dr, wheelbase b,
#  max steer in degrees)
DESIGN_TABLE = {
    "msv": (1.8, 3.7, 1.0, 2.7, 45),
    "zoe": (1.771, 3.427, 0.657, 2.588, 33),
    "corsa": (1.532, 3.212, 0.410, 2.343, 32),
    "vw": (1.994, 3.308, 1.192, 3.400, 36),
    "benz": (1.939, 3.528, 1.016, 2.630, 32),
    "altis": (1.780, 3.515, 0.815, 2.700, 28),
    "vclass": (1.928, 4.400, 0.970, 3.430, 29),
}
