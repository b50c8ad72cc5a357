#pragma once
/// @file mitsuba_daylight.h
/// What Mitsuba 0.6's daylight emitters (`sky`, `sun`, `sunsky`) emit at scale 1, in the scale of Mitsuba's RGB
/// renderer (a spectral radiance in W/(m² sr nm) shown as its ȳ-weighted mean over the band, common/color/spectrum_rgb.h),
/// for the Mitsuba reader's mapping onto the Preetham sky and a directional sun (docs/scene-format.md):
/// - the **sky's horizontal illuminance** Y_h = ∫ Y(ω) cos θ dω over the upper hemisphere (Y: the Rec. 709 luminance
///   of its RGB), tabulated for turbidity 1–10 and the sun 0–90° above the horizon at Mitsuba's default ground albedo
///   0.2. The values were measured by integrating Mitsuba 0.6's sky (the Hošek–Wilkie 2012 RGB model divided by
///   106.856980, Σ ȳ, as its `sky` plugin does) on a 96 × 192 grid in (cos θ, φ); between the nodes they are
///   interpolated linearly, within 1.3% of the model in the sun's elevation and 3.7% in the turbidity (at integer
///   turbidities 1.3%);
/// - the **sun's radiance**: Preetham, Shirley & Smits (1999), appendix A.2: the extraterrestrial solar radiance
///   attenuated by Rayleigh scattering, Ångström aerosols (β = 0.04608 T − 0.04586, α = 1.3), ozone (0.35 cm),
///   mixed gases and water vapour (2 cm) along Kasten's relative air mass, tabulated every 5 nm from 350 to 800 nm;
///   the absorption coefficients and the solar spectrum are Iqbal's (1983, "An Introduction to Solar Radiation",
///   pp. 115–132) as that paper uses them. Mitsuba's sun disk has a radius of 0.2679° (0.5358° across).
#include "common/util/math.h"

namespace firstshot::mitsuba {

/// Y_h of Mitsuba 0.6's sky at scale 1 (see the file comment) for turbidity @p turbidity (limited to [1, 10]) and the
/// sun @p elevationDeg above the horizon (limited to [0, 90]).
double skyHorizontalLuminance(double turbidity, double elevationDeg);

/// The sun's radiance in Mitsuba's RGB scale, W/(m² sr) per channel, for turbidity @p turbidity and the sun's zenith
/// angle @p zenithRad (< π/2); each channel ≥ 0.
Color sunRadiance(double turbidity, double zenithRad);

/// Solid angle of Mitsuba's sun disk, sr: 2π (1 − cos 0.2679°).
double sunSolidAngle();

}  // namespace firstshot::mitsuba
