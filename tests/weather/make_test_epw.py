#!/usr/bin/env python3
"""Writes tests/weather/boulder-week.epw: a week of made-up weather (19–25 June) in the EPW format,
for lambert's reader and Perez sky tests (load/epw_test.cpp, light/perez_sky_test.cpp). Not a
climate: each day is one kind of sky (clear, overcast, partly cloudy, hazy, ...) so that the
hours span the Perez clearness bins. The sun comes from a textbook formula (Spencer's declination
and equation of time), which is all the irradiances need; global = direct·cos Z + diffuse, and the
illuminances are the irradiances × fixed efficacies (diffuse 120 lm/W, direct 95 lm/W), a file's
data rather than a model lambert uses.

    python3 tests/weather/make_test_epw.py > tests/weather/boulder-week.epw
    python3 tests/weather/make_test_epw.py --year > year.epw   # 8,760 hours, the seven kinds in turn

The year (for `make bench`'s annual daylight, never committed) repeats the week's seven kinds of
day through a non-leap year, with each day's own sun.
"""
import math
import sys

LAT, LON, TZ, ELEV = 40.02, -105.25, -7.0, 1650.0
# Per day: (direct normal at air mass 1 in W/m², its attenuation per air mass, diffuse scale in W/m²
# at the zenith sun, a flicker of clouds 0–1).
DAYS = [(950, 0.14, 80, 0.0), (0, 0, 260, 0.0), (600, 0.25, 180, 0.6), (820, 0.20, 140, 0.2),
        (300, 0.35, 300, 0.3), (1000, 0.12, 60, 0.0), (120, 0.5, 330, 0.5)]


def sun_cos_zenith(day_of_year, hour_middle):
    g = 2 * math.pi / 365 * (day_of_year - 1 + (hour_middle - 12) / 24)
    decl = (0.006918 - 0.399912 * math.cos(g) + 0.070257 * math.sin(g) - 0.006758 * math.cos(2 * g)
            + 0.000907 * math.sin(2 * g) - 0.002697 * math.cos(3 * g) + 0.00148 * math.sin(3 * g))
    eot = 229.18 * (0.000075 + 0.001868 * math.cos(g) - 0.032077 * math.sin(g) - 0.014615 * math.cos(2 * g)
                    - 0.040849 * math.sin(2 * g))
    solar_minutes = hour_middle * 60 + eot + 4 * LON - 60 * TZ
    hour_angle = math.radians(solar_minutes / 4 - 180)
    lat = math.radians(LAT)
    return math.sin(lat) * math.sin(decl) + math.cos(lat) * math.cos(decl) * math.cos(hour_angle)


MONTH_DAYS = [31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31]


def main():
    year = "--year" in sys.argv[1:]
    print(f"LOCATION,Boulder Test,CO,USA,lambert synthetic,724699,{LAT:.2f},{LON:.2f},{TZ:.1f},{ELEV:.1f}")
    print("DESIGN CONDITIONS,0")
    print("TYPICAL/EXTREME PERIODS,0")
    print("GROUND TEMPERATURES,0")
    print("HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0")
    print("COMMENTS 1,\"Made up by tests/weather/make_test_epw.py for lambert's tests; not a climate\"")
    print("COMMENTS 2,one kind of sky a day")
    print("DATA PERIODS,1,1,Data,Saturday, 1/1,12/31" if year else "DATA PERIODS,1,1,Data,Wednesday, 6/19, 6/25")
    dates = [(m + 1, day) for m in range(12) for day in range(1, MONTH_DAYS[m] + 1)] if year else [(6, 19 + d) for d in range(7)]
    for date_index, (month, day) in enumerate(dates):
        d = date_index % 7
        dni0, tau, dif0, flicker = DAYS[d]
        doy = sum(MONTH_DAYS[:month - 1]) + day
        for hour in range(1, 25):
            mu = sun_cos_zenith(doy, hour - 0.5)
            if mu > 0.01:
                air_mass = 1 / (mu + 0.15 * (93.885 - math.degrees(math.acos(mu))) ** -1.253)
                cloud = 1 - flicker * (0.5 + 0.5 * math.sin(3.7 * hour + d))
                dni = dni0 * math.exp(-tau * (air_mass - 1)) * cloud
                dhi = dif0 * mu ** 0.6 * (1 + 0.3 * (1 - cloud))
            elif mu > -0.1:  # twilight: a little diffuse light, no sun
                dni, dhi = 0.0, 8.0 * (mu + 0.1) / 0.11
            else:
                dni, dhi = 0.0, 0.0
            dni, dhi = round(dni), round(dhi)
            ghi = round(dhi + dni * max(mu, 0))
            ill = (round(ghi and (dhi * 120 + dni * max(mu, 0) * 95)), round(dni * 95), round(dhi * 120))
            dry = 18 + 9 * math.sin((hour - 9) / 24 * 2 * math.pi) - 3 * (dif0 > 250)
            dew = 6 + 4 * (dif0 > 250) + 0.5 * d
            fields = [2005, month, day, hour, 0, "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9", f"{dry:.1f}", f"{dew:.1f}", 50,
                      83500, 0, 0, 350, ghi, dni, dhi, ill[0], ill[1], ill[2], 0, 180, 2.1, 5, 3, 30.0, 77777, 9,
                      999999999, 15, 0.08, 0, 88, 0.2, 0.0, 0.0]
            print(",".join(str(x) for x in fields))


main()
