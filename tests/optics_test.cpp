// Fresnel, Snell and total internal reflection against closed forms.
#include <array>
#include <cmath>

#include <gtest/gtest.h>

#include "area_light.h"
#include "cpu/triangle_intersection.h"
#include "optics.h"
#include "random.h"
#include "scene/shading_inputs.h"
#include "surface_response.h"

namespace vkrt {
namespace {

using namespace shading;

bool refract(const glm::dvec3& toViewer, const glm::dvec3& normal, double eta, glm::dvec3& transmitted) {
    return refractThrough(toViewer, normal, eta, transmitted);
}
glm::dvec3 reflect(const glm::dvec3& toViewer, const glm::dvec3& normal) {
    return reflectAbout(toViewer, normal);
}
SurfaceMaterial untextured(const Material& material) {
    std::vector<gpu::GpuTextureBinding> bindings;
    return surfaceMaterial(material, {}, bindings);
}

glm::dvec3 fromAngle(double theta) {
    return {std::sin(theta), 0.0, std::cos(theta)};
}  // normal is +z

TEST(Fresnel, NormalIncidence) {
    EXPECT_NEAR(fresnelDielectric(1.0, 1.5), 0.04, 1e-15);  // ((n - 1) / (n + 1))^2
    EXPECT_NEAR(fresnelDielectric(1.0, 1.333), std::pow(0.333 / 2.333, 2), 1e-15);
    EXPECT_NEAR(fresnelDielectric(1.0, 1.0 / 1.5), 0.04, 1e-15);  // the same from inside
    EXPECT_DOUBLE_EQ(dielectricF0(1.5), 0.04);
}

TEST(Fresnel, GrazingIncidenceReflectsEverything) {
    EXPECT_DOUBLE_EQ(fresnelDielectric(0.0, 1.5), 1.0);
    EXPECT_GT(fresnelDielectric(std::cos(89.9 * M_PI / 180.0), 1.5), 0.98);
    // Monotonic from Brewster's angle to grazing.
    double previous = 0.0;
    for (double degrees = 57.0; degrees < 90.0; degrees += 1.0) {
        const double f = fresnelDielectric(std::cos(degrees * M_PI / 180.0), 1.5);
        EXPECT_GT(f, previous) << degrees;
        previous = f;
    }
}

TEST(Fresnel, BrewsterAngleLeavesOnlyTheSPolarisation) {
    // At tan(theta) = n the p-polarised reflectance vanishes; the s part follows from Snell's law.
    const double n = 1.5, theta = std::atan(n);
    const double thetaT = std::asin(std::sin(theta) / n);
    EXPECT_NEAR(theta + thetaT, M_PI / 2, 1e-12);  // at Brewster's angle the two rays are perpendicular
    const double rs = std::sin(theta - thetaT) / std::sin(theta + thetaT);  // Fresnel's sine law
    EXPECT_NEAR(fresnelDielectric(std::cos(theta), n), 0.5 * rs * rs, 1e-12);
}

TEST(Fresnel, IndexMatchedInterfaceIsInvisible) {
    for (double c = 0.05; c <= 1.0; c += 0.05) EXPECT_NEAR(fresnelDielectric(c, 1.0), 0.0, 1e-15);
}

TEST(Snell, RefractionObeysSnellsLaw) {
    const glm::dvec3 normal(0, 0, 1);
    for (double degrees : {0.0, 10.0, 30.0, 60.0, 89.0}) {
        const double theta = degrees * M_PI / 180.0;
        glm::dvec3 t;
        ASSERT_TRUE(refract(fromAngle(theta), normal, 1.5, t));
        EXPECT_NEAR(glm::length(t), 1.0, 1e-14);
        EXPECT_LT(t.z, 0.0);                                         // goes into the surface
        EXPECT_NEAR(-t.x, std::sin(theta) / 1.5, 1e-14) << degrees;  // n1 sin(i) = n2 sin(t)
        EXPECT_NEAR(t.y, 0.0, 1e-15);                                // stays in the plane of incidence
    }
}

TEST(Snell, TotalInternalReflectionPastTheCriticalAngle) {
    const double eta = 1.0 / 1.5;  // glass to air
    const double critical = std::asin(eta);
    EXPECT_NEAR(critical * 180.0 / M_PI, 41.8103, 1e-4);
    glm::dvec3 t;
    EXPECT_TRUE(refract(fromAngle(critical - 1e-6), {0, 0, 1}, eta, t));
    EXPECT_FALSE(refract(fromAngle(critical + 1e-6), {0, 0, 1}, eta, t));
    EXPECT_LT(fresnelDielectric(std::cos(critical - 1e-3), eta), 1.0);
    EXPECT_DOUBLE_EQ(fresnelDielectric(std::cos(critical + 1e-6), eta), 1.0);
    EXPECT_DOUBLE_EQ(fresnelDielectric(std::cos(1.2), eta), 1.0);
}

TEST(Snell, ReflectionMirrorsAboutTheNormal) {
    const glm::dvec3 r = reflect(fromAngle(0.3), {0, 0, 1});
    EXPECT_NEAR(r.x, -std::sin(0.3), 1e-15);
    EXPECT_NEAR(r.z, std::cos(0.3), 1e-15);
}

// Normals in or next to the plane z = 0 (a Y-up scene's walls), whose z is 0, -0 or a rounding error of
// either sign that differs between devices, take one branch of the basis: their bases differ by about as much
// as the normals do. With the branches parting at z = 0, a wall's z of -1.1e-7 (its face normal in float, on
// the GPU) against +0 (its file's vertex normal, on the CPU) turned the basis by 180 degrees about the
// normal.
TEST(OrthonormalBasis, NormalsBesideThePlaneZEqualsZeroShareABasis) {
    for (const glm::dvec3 wall :
         {glm::dvec3(1, 0, 0), glm::dvec3(0.6, -0.8, 0), glm::dvec3(-0.999932, 0.011661, 0)}) {
        glm::dvec3 t0, b0;
        orthonormalBasis(glm::normalize(wall), t0, b0);
        for (const double z : {-0.0, 1.1e-7, -1.1e-7, 1e-4, -1e-4}) {
            glm::dvec3 t, b;
            orthonormalBasis(glm::normalize(wall + glm::dvec3(0.0, 0.0, z)), t, b);
            EXPECT_LT(glm::length(t - t0), 1e-3) << "z " << z;
            EXPECT_LT(glm::length(b - b0), 1e-3) << "z " << z;
        }
    }
}

TEST(OrthonormalBasis, IsOrthonormalAndRightHandedOnEitherSideOfItsSeam) {
    for (const double z : {1.0, 0.5, 0.0, -0.4142, -0.4143, -0.9, -0.999999, -1.0}) {
        const double r = std::sqrt(1.0 - z * z);
        const glm::dvec3 n(0.6 * r, 0.8 * r, z);
        glm::dvec3 t, b;
        orthonormalBasis(n, t, b);
        EXPECT_NEAR(glm::length(t), 1.0, 1e-9) << "z " << z;
        EXPECT_NEAR(glm::length(b), 1.0, 1e-9) << "z " << z;
        EXPECT_NEAR(glm::dot(t, b), 0.0, 1e-9) << "z " << z;
        EXPECT_NEAR(glm::dot(t, n), 0.0, 1e-9) << "z " << z;
        EXPECT_LT(glm::length(glm::cross(t, b) - n), 1e-9) << "z " << z;
    }
}

TEST(GlassSlab, RayLeavesParallelAndShiftedByTheAnalyticAmount) {
    // A slab between z = 0 and z = -d, made of two large triangles per face, traced with the renderer's
    // intersection and refraction code.
    const double d = 0.37, n = 1.5;
    const Triangle top{{-100, -100, 0}, {100, -100, 0}, {0, 100, 0}, 0};
    const Triangle bottom{{-100, -100, static_cast<float>(-d)},
                          {0, 100, static_cast<float>(-d)},
                          {100, -100, static_cast<float>(-d)},
                          0};
    for (double degrees : {5.0, 25.0, 45.0, 70.0, 85.0}) {
        const double theta = degrees * M_PI / 180.0;
        const glm::dvec3 direction = -fromAngle(theta);  // coming down towards the slab
        const glm::dvec3 origin = glm::dvec3(0.1, 0.2, 0.0) - 5.0 * direction;
        TriangleHit hit;
        ASSERT_TRUE(intersectTriangle(top, origin, direction, 0.0, 1e9, hit));
        const glm::dvec3 entry = origin + hit.t * direction;
        glm::dvec3 inside;
        ASSERT_TRUE(refract(-direction, {0, 0, 1}, n, inside));
        ASSERT_TRUE(intersectTriangle(bottom, entry, inside, 0.0, 1e9, hit));
        const glm::dvec3 exit = entry + hit.t * inside;
        glm::dvec3 outside;
        ASSERT_TRUE(refract(-inside, {0, 0, 1}, 1.0 / n, outside));  // normal on the incident side
        EXPECT_NEAR(glm::length(glm::cross(outside, direction)), 0.0, 1e-12) << "parallel at " << degrees;
        EXPECT_GT(glm::dot(outside, direction), 0.0);
        // Lateral displacement: d sin(theta - theta_t) / cos(theta_t).
        const double thetaT = std::asin(std::sin(theta) / n);
        const double expected = d * std::sin(theta - thetaT) / std::cos(thetaT);
        const glm::dvec3 offset = exit - entry;
        const double shift = glm::length(offset - glm::dot(offset, direction) * direction);
        EXPECT_NEAR(shift, expected, 1e-6 * d) << degrees;
    }
}

// Midpoint quadrature over the hemisphere around +z of f(direction) d(omega).
template <typename F>
double hemisphereIntegral(F f, int thetaSteps = 600, int phiSteps = 600) {
    double sum = 0.0;
    const double dTheta = 0.5 * M_PI / thetaSteps, dPhi = 2.0 * M_PI / phiSteps;
    for (int i = 0; i < thetaSteps; ++i) {
        const double theta = (i + 0.5) * dTheta;
        for (int j = 0; j < phiSteps; ++j) {
            const double phi = (j + 0.5) * dPhi;
            const glm::dvec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
            sum += f(w) * std::sin(theta) * dTheta * dPhi;
        }
    }
    return sum;
}

TEST(Microfacet, GgxDistributionIsNormalised) {
    // Projected microfacet area equals the macro surface: the integral of D(h) cos(theta_h) is 1.
    for (double alpha : {0.1, 0.5, 1.0}) {
        const double integral = hemisphereIntegral(
            [&](const glm::dvec3& h) { return ggxD(glm::dvec3(0.0, 0.0, 1.0), h, alpha) * h.z; }, 2000, 64);
        EXPECT_NEAR(integral, 1.0, 2e-3) << "alpha " << alpha;
    }
}

TEST(Microfacet, VisibleNormalSamplingMatchesItsDensity) {
    // The mean of G2 / G1 over sampled reflections equals the hemispherical integral of the F = 1 lobe,
    // D G2 / (4 cos_o), and ggxReflectionPdf integrates over the upper hemisphere to the fraction of samples
    // that land there: the sampler draws what the density says. The integral stays below 1 (energy never
    // grows).
    for (double alpha : {0.2, 0.6, 1.0}) {
        for (double thetaOut : {0.3, 1.2}) {
            const glm::dvec3 out(std::sin(thetaOut), 0.0, std::cos(thetaOut));
            double sampled = 0.0;
            int above = 0;
            constexpr int samples = 200000;
            for (int s = 0; s < samples; ++s) {
                const glm::dvec3 m =
                    sampleGgxVisibleNormal(out, alpha, vkrtRandom(1, s, 0, 0), vkrtRandom(1, s, 0, 1));
                const glm::dvec3 in = reflect(out, m);
                if (in.z > 0.0) {
                    sampled += ggxG2(out.z, in.z, alpha) / ggxG1(out.z, alpha);
                    ++above;
                }
            }
            sampled /= samples;
            const double integral = hemisphereIntegral([&](const glm::dvec3& in) {
                const glm::dvec3 h = glm::normalize(in + out);
                return ggxD(glm::dvec3(0.0, 0.0, 1.0), h, alpha) * ggxG2(out.z, in.z, alpha) / (4.0 * out.z);
            });
            const double density = hemisphereIntegral([&](const glm::dvec3& in) {
                return ggxReflectionPdf(out.z, glm::dvec3(0.0, 0.0, 1.0), glm::normalize(in + out), alpha);
            });
            EXPECT_NEAR(sampled, integral, 0.005) << "alpha " << alpha << " theta " << thetaOut;
            EXPECT_LE(integral, 1.0);
            // The density over the upper hemisphere is the fraction of sampled reflections that land there.
            EXPECT_NEAR(density, static_cast<double>(above) / samples, 0.005)
                << "alpha " << alpha << " theta " << thetaOut;
        }
    }
}

TEST(WhittedModel, LambertPartAndMirrorLobe) {
    // Lambert part: a white diffuse surface reflects albedo / pi per unit irradiance.
    Material white;
    white.metallic = 0.0f;
    white.ior = 1.0f;  // no specular reflectance
    const SurfaceResponse s =
        surfaceResponse(untextured(white), untexturedSample(untextured(white), glm::dvec3(1.0)));
    EXPECT_NEAR(s.diffuse.x / M_PI, 1.0 / M_PI, 1e-15);
    EXPECT_FALSE(s.traced);  // matte: the lobe is lit by lights only
    EXPECT_NEAR(specularBrdf(s, {0, 0, 1}, fromAngle(0.4), fromAngle(-0.9)).x, 0.0, 1e-15);
    // A mirror has a delta lobe: no response to lights, no density for multiple importance sampling.
    Material mirror;
    mirror.roughness = 0.0f;
    const SurfaceResponse m =
        surfaceResponse(untextured(mirror), untexturedSample(untextured(mirror), glm::dvec3(1.0)));
    EXPECT_TRUE(m.mirror && m.traced);
    EXPECT_EQ(specularBrdf(m, {0, 0, 1}, fromAngle(0.4), fromAngle(-0.4)), glm::dvec3(0.0));
    EXPECT_EQ(lobePdf(m, {0, 0, 1}, {0, 0, 1}, fromAngle(0.4), fromAngle(-0.4)), 0.0);
}

// The integral of max(0, n . w) over the directions w a triangle covers seen from `from`: Lambert's formula
// for a polygon, half the sum over its edges of the angle each subtends times n . the unit normal of the
// plane through it and `from` (Arvo 1995), for a triangle wholly above n's horizon.
double projectedSolidAngle(const std::array<glm::dvec3, 3>& corners, const glm::dvec3& from,
                           const glm::dvec3& n) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 p = glm::normalize(corners[i] - from),
                         q = glm::normalize(corners[(i + 1) % 3] - from);
        sum += std::atan2(glm::length(glm::cross(p, q)), glm::dot(p, q)) *
               glm::dot(n, glm::normalize(glm::cross(p, q)));
    }
    return 0.5 * std::abs(sum);
}

TEST(AreaLights, TriangleSamplesFallWhereTheirDensitySays) {
    // Stratified samples of a triangle seen from near (where it covers 3.4 sr) and from farther (0.33 sr),
    // where it looks large and is sampled by solid angle, and from far away (7e-4 and 7e-6 sr), where it is
    // sampled by area, as it is everywhere in scenes without a large lamp (`bySolidAngle` false), estimate
    // the projected solid angle for three normals as Lambert's formula gives it: the points fall where their
    // density says. Every point's density matches the one multiple importance sampling asks for, and the
    // solid angle (Van Oosterom and Strackee's) Girard's, from the triangle's angles.
    const std::array<glm::dvec3, 3> corners = {glm::dvec3(0, 0, 1), glm::dvec3(2, 0, 1),
                                               glm::dvec3(0, 3, 1.5)};
    const double area = triangleArea(corners[0], corners[1], corners[2]);
    for (const bool allowed : {true, false}) {
        for (const glm::dvec3 from : {glm::dvec3(0.4, 0.6, 0.7), glm::dvec3(1.0, 1.0, 4.0),
                                      glm::dvec3(30.0, -20.0, 50.0), glm::dvec3(300.0, -200.0, 500.0)}) {
            const SphericalTriangle spherical = sphericalTriangle(corners[0], corners[1], corners[2], from);
            const bool bySolidAngle =
                allowed && sampledSphericalTriangle(corners[0], corners[1], corners[2], from).area > 0.0;
            EXPECT_EQ(bySolidAngle, allowed && glm::length(from) < 10.0) << "solid angle " << spherical.area;
            // Girard's theorem: the angles at the corners sum to pi plus the solid angle.
            double angles = 0.0;
            for (int i = 0; i < 3; ++i) {
                const glm::dvec3 p = corners[i] - from, q = corners[(i + 1) % 3] - from,
                                 r = corners[(i + 2) % 3] - from;
                const glm::dvec3 toQ = glm::cross(p, q), toR = glm::cross(p, r);
                angles += std::acos(glm::dot(toQ, toR) / (glm::length(toQ) * glm::length(toR)));
            }
            EXPECT_NEAR(spherical.area, angles - M_PI, 1e-9 * spherical.area);
            // Normals facing the triangle: its own (every direction to it above the horizon) and two tilted
            // ones, used where the triangle stays above their horizon too.
            glm::dvec3 facing = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
            if (glm::dot(facing, corners[0] - from) < 0.0) facing = -facing;
            const glm::dvec3 side = glm::normalize(glm::cross(facing, glm::dvec3(0.3, 1.0, 0.2)));
            int checked = 0;
            for (const glm::dvec3 n :
                 {facing, glm::normalize(facing + 0.3 * side), glm::normalize(facing - 0.2 * side)}) {
                bool above = true;
                for (const glm::dvec3& corner : corners) above = above && glm::dot(n, corner - from) > 0.0;
                if (!above) continue;
                ++checked;
                constexpr int strata = 300;
                double sum = 0.0;
                for (int i = 0; i < strata; ++i) {
                    for (int j = 0; j < strata; ++j) {
                        const double u = (i + 0.5) / strata, v = (j + 0.5) / strata;
                        const LightPoint p = sampleTriangleLight(7u, corners[0], corners[1], corners[2], 1.0,
                                                                 1.0 / area, from, allowed, u, v);
                        const glm::dvec3 offset = p.position - from;
                        const double distance2 = glm::dot(offset, offset);
                        const glm::dvec3 w = offset / std::sqrt(distance2);
                        const double cosLight = std::abs(glm::dot(p.normal, w));
                        const double pdf = p.pdfArea * distance2 / cosLight;  // per solid angle
                        ASSERT_NEAR(
                            pdf,
                            triangleLightSolidAnglePdf(corners[0], corners[1], corners[2], 1.0, 1.0 / area,
                                                       from, allowed, distance2, cosLight),
                            1e-9 * pdf);
                        sum += std::max(0.0, glm::dot(n, w)) / pdf;
                    }
                }
                const double expected = projectedSolidAngle(corners, from, n);
                EXPECT_NEAR(sum / (strata * strata), expected, 2e-4 * expected)
                    << "from " << from.x << " n " << n.x << (allowed ? "" : ", by area");
            }
            EXPECT_GE(checked, 2);
        }
    }
}

}  // namespace
}  // namespace vkrt
