#pragma once
/// @file bsdf.h
/// BSDFs in the local shading frame (z = normal), Nori / pbrt-v4 style.
///
/// Conventions
/// - wo and wi are unit vectors pointing AWAY from the surface: wo towards the viewer (or the
///   previous path vertex), wi towards the light (or the next vertex). f(wi, wo) is the BSDF, so
///   reflected radiance is L_o(wo) = ∫ f(wi, wo) L_i(wi) |cos θ_i| dω_i.
/// - The caller passes directions in the frame of the geometric normal as stored in the mesh (its
///   front side is z > 0) and need not flip anything:
///   * Reflection models (Lambert, stretched Phong, mirror, metallic-roughness) are two-sided: they depend on |cos θ|
///     only and are zero unless wi and wo lie on the same side (wi.z·wo.z > 0). Flipping the frame
///     so that wo.z > 0 (as a renderer may do for two-sided surfaces) is therefore harmless.
///   * The smooth dielectric reads the side from the sign of wo.z: wo.z > 0 is outside (index 1),
///     wo.z < 0 inside (index ior). For it the frame must NOT be flipped: use the outward normal.
/// - A direction with z == 0 (grazing) gets zero BSDF and sample() fails there.
///
/// Delta lobes (mirror, dielectric, thin glass): eval() and pdf() return 0 (a delta cannot be hit by a direction
/// chosen elsewhere); sample() sets specular = true and pdf = the discrete probability of having
/// chosen that lobe (1 for the mirror, R or 1−R for the dielectric). That pdf is not a solid-angle
/// density and must not enter MIS against one.
#include <cstdint>
#include <optional>
#include <variant>

#include "common/materials/conductor_fresnel.h"
#include "common/materials/bsdf_query.h"
#include "common/materials/microfacet_model.h"
#include "common/materials/rough_dielectric.h"
#include "common/materials/thin_glass.h"
#include "common/util/math.h"

namespace firstshot {

struct MaterialDesc;

// Each model below has the same four members:
//   Color sample(BSDFQuery& q, const Vec2& u) const
//       Draws wi for q.wo from u ∈ [0,1)², sets q.wi, q.pdf, q.specular, q.eta and returns the
//       sample weight f(wi,wo)·|cos θ_i| / pdf (for a delta lobe: the lobe's reflectance or
//       transmittance divided by its selection probability). Returns 0 (and q.pdf = 0) on failure,
//       e.g. a lobe sample below the horizon; then q.wi is unspecified.
//   Color eval(const BSDFQuery& q) const  -> f(wi, wo) in 1/sr; 0 for delta lobes. Radiance mode: light from wi
//                                            leaving along wo; Importance mode the adjoint f(wo → wi) (wo the side a
//                                            particle came from, as in sample()). They differ only across a
//                                            refraction (rough glass, common/materials/rough_dielectric.h), by η².
//   float pdf(const BSDFQuery& q) const   -> solid-angle density with which sample() draws q.wi
//                                            given q.wo; 0 for delta lobes.
//   Color albedo() const                  -> a reflectance-like colour for AOVs (see each model).

/// Lambertian reflector: f = ρ/π (two-sided). Samples cos θ_i/π; the weight is exactly ρ.
struct LambertBRDF {
  Color rho{0.5f};  ///< diffuse reflectance ρ ∈ [0,1]³
  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery& q) const;
  float pdf(const BSDFQuery& q) const;
  Color albedo() const { return rho; }
};

/// Stretched ("max") Phong of Neumann, Neumann & Szirmay-Kalos (1999), the non-diffuse model of the
/// incoming first-shot paper (which names it and cites it as [14] without printing the formula),
/// plus a Lambertian part:
///   f(wi, wo) = ρd/π + ks · max(0, R·V)^n / max(cos θ_i, cos θ_o),
/// with R·V = reflect(wi)·wo = wi·reflect(wo) (symmetric, so f is reciprocal).
/// Energy: the glossy directional albedo is a(θ_o) = ks ∫ cos^n ψ · cos θ_i / max(cos θ_i, cos θ_o) dω_i
/// ≤ ks ∫_{ψ<π/2} cos^n ψ dω = ks · 2π/(n+1), because the cosine ratio is ≤ 1. Hence the lobe
/// conserves energy for every incidence angle iff ks ≤ (n+1)/(2π) (glossyEnergyBound); the whole
/// BRDF does when Σ ρd + ks·2π/(n+1) ≤ 1 per channel. Exact values: a(0°) = ks·2π/(n+2),
/// a(→90°) = ks·π/(n+1).
/// Sampling: one-sample mixture of cosine sampling (probability pd) and the Phong lobe
/// (n+1)/(2π)·cos^n ψ around reflect(wo) (probability 1−pd), with pd = mean(ρd)/(mean(ρd) +
/// mean(ks)·2π/(n+2)); pdf() is the mixture density pd·cos θ_i/π + (1−pd)·(n+1)/(2π)·cos^n ψ,
/// and lobe samples below the horizon fail (weight 0), so ∫pdf over the hemisphere may be < 1.
struct StretchedPhongBRDF {
  Color rhoD{0.0f};  ///< diffuse reflectance ρd
  Color ks{0.0f};    ///< glossy coefficient (1/sr); energy-conserving when ≤ glossyEnergyBound(n)
  float n = 1.0f;    ///< Phong exponent ("shine"), ≥ 0; the first-shot paper uses 3
  float pDiffuse = 1.0f;  ///< probability of sampling the diffuse part (set by the constructor)

  StretchedPhongBRDF() = default;
  StretchedPhongBRDF(const Color& rhoD_, const Color& ks_, float n_);
  /// Largest ks for which the glossy lobe alone never reflects more than it receives: (n+1)/(2π).
  static float glossyEnergyBound(float n) { return (n + 1.0f) * 0.5f * kInvPiF; }

  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery& q) const;
  float pdf(const BSDFQuery& q) const;
  /// ρd + ks·2π/(n+2): the total directional albedo at normal incidence.
  Color albedo() const { return rhoD + ks * (2.0f * kPiF / (n + 2.0f)); }
};

/// Perfect mirror with tint: reflects wo about the normal, weight = tint (delta lobe, two-sided); with a conductor's
/// Fresnel (common/materials/conductor_fresnel.h), weight = tint × F(|cos θ_o|), as Mitsuba's smooth `conductor`.
struct MirrorBRDF {
  Color tint{1.0f};  ///< reflectance (with a Fresnel: the factor on it)
  std::optional<ConductorFresnel> fresnel;  ///< unset: the same reflectance at every angle

  MirrorBRDF() = default;
  MirrorBRDF(const Color& tint_, const std::optional<ConductorFresnel>& fresnel_ = std::nullopt)  // NOLINT: implicit
      : tint(tint_), fresnel(fresnel_) {}
  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery&) const { return Color(0.0f); }
  float pdf(const BSDFQuery&) const { return 0.0f; }
  /// tint, times the Fresnel's cosine-weighted hemispherical mean when there is one.
  Color albedo() const { return fresnel ? tint * fresnel->hemisphericalMean() : tint; }
};

/// Smooth dielectric interface (outside index 1, inside index ior; the normal points outside).
/// sample() reflects with probability R = Fresnel(|cos θ_o|) (weight 1, eta = 1) and otherwise
/// refracts (weight = transmittance · 1/η² in Radiance mode, transmittance in Importance mode,
/// q.eta = η = η(wi side)/η(wo side): ior when entering, 1/ior when leaving). The 1/η² is the
/// change of radiance across the interface (L/η² is invariant), so radiance inside glass seen
/// from outside is divided by ior². Beyond the critical angle (from inside, sin θ_o > 1/ior) R = 1.
struct DielectricBSDF {
  float ior = 1.5f;            ///< η_inside/η_outside, > 0
  Color transmittance{1.0f};   ///< tint applied on each refraction
  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery&) const { return Color(0.0f); }
  float pdf(const BSDFQuery&) const { return 0.0f; }
  Color albedo() const { return transmittance; }
};

/// The glTF 2.0 metallic-roughness BRDF (the glTF specification's appendix B), two-sided, reflection
/// only. With the GGX specular lobe s(wi, wo) = D(h)·G2(wi, wo)/(4 cos θ_i cos θ_o) of α = ggxAlpha(roughness)
/// (common/materials/microfacet.h: α = roughness², floored at 1e-3, so roughness 0 is a very sharp lobe, not a delta),
/// h = normalize(wi + wo), c = wo·h = wi·h and Schlick's F(x) = F0 + (1 − F0)(1 − x)⁵:
///   metal      = s · F_b(c)                                    (F0 = base colour b)
///   dielectric = F_d(c)·s + b/π · (1 − F_d(cos θ_i))(1 − F_d(cos θ_o))/(1 − F̄_d)
///                (F0 = f0 = ((ior − 1)/(ior + 1))², 0.04 at 1.5; F̄_d = f0 + (1 − f0)/21, F_d's cosine mean)
///   f = metallic · metal + (1 − metallic) · dielectric
/// One deliberate departure from appendix B: its fresnel_mix weights the diffuse base by 1 − F_d(c), which
/// reflects more than it receives at grazing incidence (measured with a white base colour: 1.31 at 80° and
/// 1.52 at 89° for roughness 0.2; tests/test_microfacet.cpp). The base here is weighted by the light the
/// coat lets through on the way in and out, (1 − F_d(cos θ_i))(1 − F_d(cos θ_o)), normalised so that at
/// normal incidence its albedo is appendix B's, b·(1 − f0): reciprocal, and ≤ 1 at every angle.
/// f is reciprocal (it depends on wi and wo only through h, c, the symmetric G2 and the product above). It
/// loses the energy of multiple scattering between microfacets (no compensation, as in the specification):
/// a white rough conductor reflects 1 − loss, the loss rising with roughness (docs/measurements.md).
/// Sampling: a one-sample mixture of the specular lobe (visible normals, Heitz 2018) with probability
/// pSpecular(wo) and the cosine-weighted diffuse lobe otherwise; pdf() is the exact mixture density.
/// baseColor is a plain field read at every query (nothing derived from it is cached), so a per-hit
/// base colour (a texture) can be substituted in a copy.
/// Two options that scene files ask for (Mitsuba's rough conductors); without them the model is the above:
/// - conductor: the metal's Fresnel is b × F_c(c), a tint times the exact Fresnel of the complex index η + ik
///   (common/materials/conductor_fresnel.h), instead of Schlick's from F0 = b; reciprocal as F_c depends on c alone.
/// - microfacet = Beckmann: the specular lobe's D, G2 and sampling are Beckmann's (common/materials/beckmann.h), same α.
struct MetallicRoughnessBRDF {
  Color baseColor{1.0f};  ///< b ∈ [0,1]³: the diffuse albedo of the dielectric, F0 of the metal (with a conductor: its tint)
  float metallic = 1.0f;  ///< ∈ [0, 1]: 1 a conductor, 0 a dielectric, blended linearly between
  float roughness = 1.0f; ///< perceptual roughness r ∈ [0, 1] (α = r²)
  float ior = 1.5f;       ///< index of refraction of the dielectric (f0 = 0.04 at 1.5)
  MicrofacetModel microfacet = MicrofacetModel::Ggx;  ///< the specular lobe's distribution
  std::optional<ConductorFresnel> conductor;  ///< set: the metal's Fresnel is b × the conductor's

  MetallicRoughnessBRDF() = default;
  MetallicRoughnessBRDF(const Color& baseColor_, float metallic_, float roughness_, float ior_,
                        MicrofacetModel microfacet_ = MicrofacetModel::Ggx,
                        const std::optional<ConductorFresnel>& conductor_ = std::nullopt)
      : baseColor(baseColor_), metallic(metallic_), roughness(roughness_), ior(ior_), microfacet(microfacet_),
        conductor(conductor_) {}

  /// Probability of sampling the specular lobe for @p cosO = |cos θ_o|: its expected share of the
  /// directional albedo (Fresnel at cos θ_o; the diffuse part weighted by 1 − F_d), in [0.02, 0.98]
  /// while there is a diffuse part, 1 without one.
  float pSpecular(float cosO) const;
  Color sample(BSDFQuery& q, const Vec2& u) const;
  Color eval(const BSDFQuery& q) const;
  float pdf(const BSDFQuery& q) const;
  /// The hemispherical mean of the Fresnel terms, ignoring masking: metallic·(b + (1−b)/21) +
  /// (1 − metallic)·(F̄ + (1 − F̄)·b) with F̄ = f0 + (1 − f0)/21 (with a conductor, b × its mean in place of the
  /// metal's b + (1−b)/21). Never 0 without a conductor (grazing light always reflects).
  Color albedo() const;

 private:
  /// The metal's Fresnel at c = wo·h: Schlick's from F0 = b, or b × the conductor's.
  Color metalFresnel(float c) const { return conductor ? baseColor * conductor->eval(c) : schlickFresnel(baseColor, c); }
};

/// A BSDF as a small value type (no heap, under 100 bytes): one of the models above, dispatched by
/// std::visit. Build one per material once and reuse it for every hit.
class BSDF {
 public:
  using Model = std::variant<LambertBRDF, StretchedPhongBRDF, MirrorBRDF, DielectricBSDF, MetallicRoughnessBRDF,
                             ThinGlassBSDF, RoughDielectricBSDF, RoughThinGlassBSDF>;
  BSDF() = default;  ///< a Lambertian with ρ = 0.5 (LambertBRDF's default)
  template <typename M>
  BSDF(const M& model) : model_(model) {}  // NOLINT: implicit by design

  /// See the model comments above for the exact contract of each call. With a shading normal (setGeometricNormal)
  /// a direction on different sides of the geometric and the shading normal gets 0 and fails sample().
  Color sample(BSDFQuery& q, const Vec2& u) const {
    const Color w = std::visit([&](const auto& m) { return m.sample(q, u); }, model_);
    if (shaded_ && !sidesAgree(q)) return q.pdf = 0.0f, Color(0.0f);
    return w;
  }
  Color eval(const BSDFQuery& q) const {
    if (shaded_ && !sidesAgree(q)) return Color(0.0f);
    return std::visit([&](const auto& m) { return m.eval(q); }, model_);
  }
  float pdf(const BSDFQuery& q) const {
    return std::visit([&](const auto& m) { return m.pdf(q); }, model_);
  }
  Color albedo() const {
    return std::visit([](const auto& m) { return m.albedo(); }, model_);
  }
  /// True only for a purely Lambertian BSDF (irradiance caching may replace it by E·ρ/π) in the geometric frame (a
  /// shaded one's irradiance is about another normal than the patch's).
  bool isDiffuse() const { return !shaded_ && std::holds_alternative<LambertBRDF>(model_); }
  /// True if the BSDF consists of delta lobes only (eval and pdf are identically 0).
  bool hasDelta() const {
    return std::holds_alternative<MirrorBRDF>(model_) || std::holds_alternative<DielectricBSDF>(model_) ||
           std::holds_alternative<ThinGlassBSDF>(model_);
  }
  /// The thin glass pane (common/materials/thin_glass.h) this BSDF is, or nullptr: walks pass straight through it
  /// (render/scene/thin_glass_walk.h) and shadow rays cross it with its transmittance.
  const ThinGlassBSDF* thinGlass() const { return std::get_if<ThinGlassBSDF>(&model_); }
  /// True for a lobe sharper than a first-shot table resolves: a pbr surface or rough glass of roughness
  /// below kTableRoughness. The table's patch-level sum Σ e r f cannot follow such a lobe (it would lose the
  /// reflections of the replaced lights in polished metal), so the path walk lights these points by NEE to
  /// every light and lets BSDF rays count the replaced lights they meet (docs/measurements.md, pbr).
  bool tooSharpForTable() const {
    if (const auto* p = std::get_if<MetallicRoughnessBRDF>(&model_)) return p->roughness < kTableRoughness;
    if (const auto* g = std::get_if<RoughDielectricBSDF>(&model_)) return g->roughness < kTableRoughness;
    if (const auto* g = std::get_if<RoughThinGlassBSDF>(&model_)) return g->roughness < kTableRoughness;
    return false;
  }
  static constexpr float kTableRoughness = 0.3f;  ///< perceptual roughness (α = 0.09)
  /// True if light can pass through (the frame must not be flipped; see the file comment).
  bool hasTransmission() const {
    return std::holds_alternative<DielectricBSDF>(model_) || std::holds_alternative<ThinGlassBSDF>(model_) ||
           std::holds_alternative<RoughDielectricBSDF>(model_) || std::holds_alternative<RoughThinGlassBSDF>(model_);
  }
  /// Diffuse reflectance ρd of a Lambertian part that f − ρd/π leaves non-negative for every pair of
  /// directions; 0 for mirror, dielectric and metallic-roughness (whose diffuse part is weighted by
  /// 1 − F(h·wo) and so has no direction-independent lower bound above 0).
  Color diffuseAlbedo() const;

  const Model& model() const { return model_; }

  // --- Shading normals ---
  /// Makes this the BSDF of a point whose shading normal (the local z) differs from its geometric normal
  /// @p ngLocal (unit, in the shading frame, ngLocal.z > 0): eval and sample then give 0 to a direction that lies
  /// on one side of the surface and on the other of the shading normal (pbrt's and Mitsuba's rule, against light
  /// leaking through), and isDiffuse and diffuseAlbedo say 0 (the shortcuts E·ρ/π assume the geometric normal).
  /// The adjoint correction of particle paths is the integrators' (render/scene/shading_normals.h).
  void setGeometricNormal(const Vec3& ngLocal) { ngLocal_ = ngLocal, shaded_ = true; }
  /// Whether setGeometricNormal was called.
  bool shaded() const { return shaded_; }

 private:
  bool sidesAgree(const BSDFQuery& q) const {
    return glm::dot(q.wo, ngLocal_) * q.wo.z > 0.0f && glm::dot(q.wi, ngLocal_) * q.wi.z > 0.0f;
  }
  Model model_;
  Vec3 ngLocal_{0.0f, 0.0f, 1.0f};
  bool shaded_ = false;
};

/// BSDF of a material: Diffuse → Lambert(albedo); Glossy → stretched Phong(albedo, ks = specular,
/// n = exponent); Mirror → mirror(specular, conductor); Dielectric → dielectric(ior, transmittance); Pbr →
/// metallic-roughness(base colour = albedo, metallic, roughness, ior, microfacet, conductor); ThinGlass → thin
/// glass(transmittance, ior).
/// A dielectric or thin glass of glassRoughness > 0 is the rough model (common/materials/rough_dielectric.h).
/// Emission is not part of the BSDF.
BSDF makeBSDF(const MaterialDesc& material);
/// The BSDF of @p material with @p albedo in place of material.albedo: a textured material at one point
/// (render/scene/surface_textures.h), albedo = factor × texel.
BSDF makeBSDF(const MaterialDesc& material, const Color& albedo);
/// The same with a pbr material's @p metallic and @p roughness in place of the material's (its
/// metallic-roughness texture at one point); other types ignore them.
BSDF makeBSDF(const MaterialDesc& material, const Color& albedo, float metallic, float roughness);

}  // namespace firstshot
