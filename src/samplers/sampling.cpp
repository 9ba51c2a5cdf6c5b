// Point sampling: k x k samples per pixel on the regular grid or jittered in their strata,
// box-averaged or splatted through a filter (Mitsuba's film), in a fixed operation order
// (sampling.hpp).
#include <cmath>
#include <cstdint>
#include <vector>

#include "samplers/depth.hpp"
#include "samplers/sampling.hpp"

namespace aaeval::samplers {

namespace {

inline uint64_t splitmix64(uint64_t z) {
    z = z + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Adds one pixel row's samples to every pixel whose filter reaches them: w * colour to
// num (the image) and w to den, w = k(x - i - 1/2) k(y - j - 1/2).
void splat_row(int64_t r, int64_t k, bool jitter, const std::vector<double>& offsets,
               const std::vector<int64_t>& best_p, const double* colors, const double* background, const Profile& f,
               int64_t width, int64_t height, double* num, double* den) {
    const int64_t ns = k * k;
    const double inv_k = 1.0 / static_cast<double>(k);
    const int64_t reach = to_i64(std::ceil(f.radius)) + 1;
    for (int64_t col = 0; col < width; ++col) {
        for (int64_t s = 0; s < ns; ++s) {
            const int64_t j = s / k;
            const int64_t i = s - j * k;
            const double u = jitter ? offsets[(col * ns + s) * 2] : 0.5;
            const double v = jitter ? offsets[(col * ns + s) * 2 + 1] : 0.5;
            const double x = (static_cast<double>(col * k + i) + u) * inv_k;
            const double y = static_cast<double>(r) + (static_cast<double>(j) + v) * inv_k;
            const int64_t p = best_p[col * ns + s];
            const double* c = p == NO_POLYGON ? background : colors + 3 * p;
            for (int64_t py = pymax(int64_t(0), r - reach); py < pymin(height, r + reach + 1); ++py) {
                const double wy = profile_at(f, y - static_cast<double>(py) - 0.5);
                if (wy == 0.0) continue;
                for (int64_t px = pymax(int64_t(0), col - reach); px < pymin(width, col + reach + 1); ++px) {
                    const double w = wy * profile_at(f, x - static_cast<double>(px) - 0.5);
                    if (w == 0.0) continue;
                    den[py * width + px] += w;
                    double* out = num + (py * width + px) * 3;
                    for (int ch = 0; ch < 3; ++ch) out[ch] += w * c[ch];
                }
            }
        }
    }
}

}  // namespace

double jitter_uniform(uint64_t seed, int64_t row, int64_t col, int64_t sample, int64_t axis) {
    uint64_t h = splitmix64(seed);
    h = splitmix64(h ^ static_cast<uint64_t>(row));
    h = splitmix64(h ^ static_cast<uint64_t>(col));
    h = splitmix64(h ^ (static_cast<uint64_t>(sample) * 2u + static_cast<uint64_t>(axis)));
    return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);  // 53 bits
}

bool sample_image(int64_t width, int64_t height, const Polygons& P, double eps_z, const double* colors,
                  const double* background, int64_t k, bool jitter, uint64_t seed, const Profile& filter,
                  double* image) {
    std::vector<int64_t> row_start, polys;
    row_buckets(height, P, row_start, polys);
    const int64_t ns = k * k;
    EdgeBuffers E(P);
    std::vector<double> best_z(width * ns);
    std::vector<int64_t> best_p(width * ns);
    std::vector<double> offsets(jitter ? width * ns * 2 : 0);
    const bool filtered = filter.kind != KIND_BOX;
    std::vector<double> den(filtered ? height * width : 0, 0.0);
    const double inv_k = 1.0 / static_cast<double>(k);
    for (int64_t r = 0; r < height; ++r) {
        const double rd = static_cast<double>(r);
        std::fill(best_z.begin(), best_z.end(), INF);
        std::fill(best_p.begin(), best_p.end(), NO_POLYGON);
        if (jitter) {
            for (int64_t col = 0; col < width; ++col)
                for (int64_t s = 0; s < ns; ++s) {
                    offsets[(col * ns + s) * 2] = jitter_uniform(seed, r, col, s, 0);
                    offsets[(col * ns + s) * 2 + 1] = jitter_uniform(seed, r, col, s, 1);
                }
        }
        for (int64_t j = 0; j < k; ++j) {
            const double jd = static_cast<double>(j);
            const double ya = rd + jd * inv_k;
            const double yb = rd + static_cast<double>(j + 1) * inv_k;
            const double y = rd + (jd + 0.5) * inv_k;
            for (int64_t q = row_start[r]; q < row_start[r + 1]; ++q) {
                const int64_t p = polys[q];
                double xlo, xhi;
                const int64_t m = strip_edges(P, p, ya, yb, E, xlo, xhi);
                if (m == 0) continue;
                const double a = P.planes[3 * p], b = P.planes[3 * p + 1], c = P.planes[3 * p + 2];
                if (jitter) {
                    // samples of a stratum row have different y: test each one
                    const int64_t c0 = pymax(int64_t(0), to_i64(std::floor(xlo)));
                    const int64_t c1 = pymin(width - 1, to_i64(std::floor(xhi)));
                    for (int64_t col = c0; col <= c1; ++col) {
                        for (int64_t i = 0; i < k; ++i) {
                            const int64_t s = j * k + i;
                            const double x = (static_cast<double>(col * k + i) + offsets[(col * ns + s) * 2]) * inv_k;
                            const double ys = rd + (jd + offsets[(col * ns + s) * 2 + 1]) * inv_k;
                            if (inside(E, m, x, ys)) {
                                const double z = a * x + b * ys + c;
                                double& bz = best_z[col * ns + s];
                                int64_t& bp = best_p[col * ns + s];
                                if (bp == NO_POLYGON || nearer_or_tied(z, bz, eps_z)) {
                                    bz = pymin(z, bz);
                                    bp = p;
                                }
                            }
                        }
                    }
                } else {
                    // one scanline through the stratum centres: fill between crossings
                    const int64_t nc = crossings(E, m, y);
                    for (int64_t t = 0; t < nc - 1; t += 2) {
                        int64_t g0, g1;
                        grid_range(E.xc[t], E.xc[t + 1], k, width * k, g0, g1);
                        for (int64_t g = g0; g < g1; ++g) {
                            const int64_t col = g / k;
                            const int64_t s = j * k + (g - col * k);
                            const double z = a * grid_x(g, k) + b * y + c;
                            double& bz = best_z[col * ns + s];
                            int64_t& bp = best_p[col * ns + s];
                            if (bp == NO_POLYGON || nearer_or_tied(z, bz, eps_z)) {
                                bz = pymin(z, bz);
                                bp = p;
                            }
                        }
                    }
                }
            }
        }
        if (filtered) {
            splat_row(r, k, jitter, offsets, best_p, colors, background, filter, width, height, image, den.data());
            continue;
        }
        for (int64_t col = 0; col < width; ++col) {
            double* out = image + (r * width + col) * 3;
            for (int64_t s = 0; s < ns; ++s) {
                const int64_t p = best_p[col * ns + s];
                const double* c = p == NO_POLYGON ? background : colors + 3 * p;
                for (int ch = 0; ch < 3; ++ch) out[ch] += c[ch];
            }
            for (int ch = 0; ch < 3; ++ch) out[ch] /= static_cast<double>(ns);
        }
    }
    if (filtered) {
        for (int64_t i = 0; i < height * width; ++i) {
            if (den[i] == 0.0) return false;
            for (int ch = 0; ch < 3; ++ch) image[i * 3 + ch] /= den[i];
        }
    }
    return true;
}

}  // namespace aaeval::samplers
