// III.E.b of Catmull 1978: the pixel integrator. The pixel's polygon list (front to back,
// the background square last) is resolved by recursive clipping: while the front polygon F
// of a list has an edge not yet clipped along, every polygon of the list is split by that
// edge's line into two lists; once F is clipped on all sides it covers its list's region,
// and either a nearer polygon of the list moves to the front, or the list splits along the
// line where the two depth planes cross, or F is visible over the whole region.
// aaeval/catmull/reference.py is the same algorithm in a few lines of Python.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/geometry.hpp"
#include "catmull/buffers.hpp"
#include "catmull/strips.hpp"

namespace aaeval::catmull {

using geometry::EPS_LINE;

// Pieces of smaller area are dropped inside the integrator (slivers from rounding).
inline constexpr double AREA_EMPTY = 1e-15;
// A front polygon with no edge left to clip along that falls short of its list's region by
// more than 1e-9 of it AND by more than this area is a rounding remnant (is_sliver).
inline constexpr double SLIVER_SLACK = EPS_LINE;
// Safety bound on integrator steps for one pixel; never reached on valid scenes.
inline constexpr int64_t MAX_STEPS = 100000;

AAEVAL_INLINE double depth(const double* planes, int64_t p, double x, double y) {
    return planes[3 * p] * x + planes[3 * p + 1] * y + planes[3 * p + 2];
}

// Whether polygon p hides polygon q everywhere over the square [x0,x0+1]x[y0,y0+1]. Depth
// differences are linear, so the four corners decide. On one shared plane the one later in
// the file is in front (the scene format's rule).
inline bool in_front_on_square(const double* planes, int64_t p, int64_t q, double x0, double y0, double eps_z) {
    bool hides = q == BACKGROUND;
    if (q != BACKGROUND && p != BACKGROUND) {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -std::numeric_limits<double>::infinity();
        const double xs[2] = {x0, x0 + 1.0};
        const double ys[2] = {y0, y0 + 1.0};
        for (double cx : xs)
            for (double cy : ys) {
                const double d = depth(planes, p, cx, cy) - depth(planes, q, cx, cy);
                lo = pymin(lo, d);
                hi = pymax(hi, d);
            }
        hides = (hi <= eps_z && lo >= -eps_z) ? p > q : hi <= eps_z;
    }
    return hides;
}

struct Range {
    double lo, hi;
};

// The smallest and largest value of a x + b y + c over a polygon's vertices; with `keep`,
// each vertex's value too (keep[k] for vertex start + k).
AAEVAL_INLINE Range linear_range(const double* xs, const double* ys, int64_t start, int64_t n, double a, double b,
                                 double c, double* keep = nullptr) {
    Range r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (int64_t k = 0; k < n; ++k) {
        const double d = a * xs[start + k] + b * ys[start + k] + c;
        if (keep) keep[k] = d;
        r.lo = pymin(r.lo, d);
        r.hi = pymax(r.hi, d);
    }
    return r;
}

// geometry::clip_split(..., a, b, c, true, true, ...) given d[k] = a * xs[start + k] +
// b * ys[start + k] + c (linear_range's values: the expression clip_split evaluates, so the
// same doubles and the same outputs bit for bit).
AAEVAL_INLINE geometry::SplitCounts split_by_distances(const double* xs, const double* ys, const uint8_t* fs,
                                                       int64_t start, int64_t n, const double* d, double a, double b,
                                                       double c, double* oxs, double* oys, uint8_t* ofs,
                                                       int64_t astart, int64_t bstart) {
    return geometry::split_by(
        xs, ys, fs, start, n, [d, start](int64_t i) { return d[i - start]; }, a, b, c, true, true, oxs, oys, ofs,
        astart, oxs, oys, ofs, bstart);
}

// Where polygon q (the outline at start) lies in depth against polygon f's plane. 0: behind
// f everywhere on q; 1: in front everywhere on q; 2: the planes cross inside q. Tested on
// the signed distance of q's vertices to the line where the planes meet, with the clipper's
// tolerance, so after a split along that line every piece classifies cleanly.
inline int depth_relation(const double* planes, int64_t q, int64_t f, const double* xs, const double* ys, int64_t start,
                          int64_t n, double eps_z) {
    const double da = planes[3 * q] - planes[3 * f];
    const double db = planes[3 * q + 1] - planes[3 * f + 1];
    const double dc = planes[3 * q + 2] - planes[3 * f + 2];
    const double g = geometry::sqrt_ieee(da * da + db * db);
    auto [lo, hi] = linear_range(xs, ys, start, n, da, db, dc);
    if (g <= eps_z && hi <= eps_z && lo >= -eps_z) return q > f ? 1 : 0;  // one shared plane: later in front
    if (g <= eps_z) return hi < 0.0 ? 1 : 0;  // parallel planes: a constant difference decides
    lo /= g;
    hi /= g;
    if (lo >= -EPS_LINE && hi <= EPS_LINE) return lo + hi < 0.0 ? 1 : 0;  // a sliver along the crossing line
    if (lo >= -EPS_LINE) return 0;
    if (hi <= EPS_LINE) return 1;
    return 2;
}

// The integrator's workspace. Polygons are records recs[j] = (start, length, source) into
// the vertex buffer with their signed area areas[j]; `items` holds the lists' members,
// lists[L] = (first item, count), `stack` the lists still to resolve, `visible` the records
// of the visible pieces found. The sizes fit most pixels; a larger one grows them all (grow_all).
struct PixelWork {
    Verts v{4096};
    Rows<int64_t, 3> recs{1024};
    std::vector<double> areas = std::vector<double>(1024);
    std::vector<int64_t> items = std::vector<int64_t>(4096);
    Rows<int64_t, 2> lists{1024};
    std::vector<int64_t> stack = std::vector<int64_t>(1024);
    std::vector<int64_t> visible = std::vector<int64_t>(256);
    std::vector<double> dist = std::vector<double>(256);  // one polygon's distances to a line

    void grow_all() {
        v.grow_to(2 * v.size());
        recs.grow_rows(2 * recs.rows());
        grow(areas, 2 * int64_t(areas.size()));
        grow(items, 2 * int64_t(items.size()));
        lists.grow_rows(2 * lists.rows());
        grow(stack, 2 * int64_t(stack.size()));
        grow(visible, 2 * int64_t(visible.size()));
    }
};

struct PolygonsUsed {
    int64_t used, n_rec;
};

// The pixel's polygon list as integrator records, background square last if needed. Each
// listed strip piece is clipped to the pixel column; a solid piece becomes the pixel square
// with every edge flagged. Returns (vertices used, records), or (-1, 0) if the workspace is
// too small.
inline PolygonsUsed pixel_polygons(const Strip& S, const int64_t* plist, int64_t n_pl, int64_t solid, double x0,
                                   double y0, PixelWork& W) {
    double* wx = W.v.x.data();
    double* wy = W.v.y.data();
    uint8_t* wf = W.v.f.data();
    const int64_t wcap = W.v.size();
    int64_t used = 0, n_rec = 0;
    const int64_t total = n_pl + (solid < 0 ? 1 : 0);
    if (total > W.recs.rows()) used = -1;
    int64_t t = 0;
    while (t < total && used >= 0) {
        if (t < n_pl && plist[t] != solid) {
            const int64_t k = plist[t];
            const int64_t n = S.pieces[k][1];
            // the first clip goes above the space the second one (up to 4n) writes into
            const int64_t tmp = used + 4 * n + 8;
            if (tmp + 2 * n + 4 > wcap) {
                used = -1;
            } else {
                const int64_t m = geometry::clip_to_column(S.v.x.data(), S.v.y.data(), S.v.f.data(), S.pieces[k][0], n,
                                                           x0, wx, wy, wf, used, tmp);
                if (m > 0) {
                    W.areas[size_t(n_rec)] = geometry::signed_area(wx, wy, used, m);
                    n_rec = record(W.recs, n_rec, used, m, S.pieces[k][2]);
                    used += m;
                }
            }
        } else if (used + 4 > wcap) {
            used = -1;
        } else {
            const double px[4] = {x0, x0 + 1.0, x0 + 1.0, x0};
            const double py[4] = {y0, y0, y0 + 1.0, y0 + 1.0};
            for (int i = 0; i < 4; ++i) {
                wx[used + i] = px[i];
                wy[used + i] = py[i];
                wf[used + i] = 1;
            }
            W.areas[size_t(n_rec)] = geometry::signed_area(wx, wy, used, 4);
            n_rec = record(W.recs, n_rec, used, 4, t < n_pl ? S.pieces[plist[t]][2] : BACKGROUND);
            used += 4;
        }
        ++t;
    }
    return {used, used >= 0 ? n_rec : 0};
}

// Whether the front polygon of a list is much smaller than the list's region (whose area is
// the largest in the list: every list holds a polygon spanning its whole region). A
// shortfall within SLIVER_SLACK (absolute) is rounding, not a remnant.
inline bool is_sliver(const std::vector<double>& areas, const int64_t* litems, int64_t s0, int64_t cnt) {
    const int64_t f = litems[s0];
    const double area_f = areas[size_t(f)];
    double region = area_f;
    for (int64_t i = 1; i < cnt; ++i) region = pymax(region, areas[size_t(litems[s0 + i])]);
    const double shortfall = region - area_f;
    return shortfall > region * 1e-9 && shortfall > SLIVER_SLACK;
}

struct Line {
    bool found;
    double a, b, c;
};

// The line of the first unclipped, non-degenerate edge of a polygon.
inline Line first_clip_edge(const double* wx, const double* wy, const uint8_t* wf, int64_t fs, int64_t fn) {
    Line l{false, 0.0, 0.0, 0.0};
    int64_t k = 0;
    while (k < fn && !l.found) {
        if (wf[fs + k] == 0) {
            const int64_t k2 = k + 1 < fn ? fs + k + 1 : fs;
            const double ex = wx[k2] - wx[fs + k];
            const double ey = wy[k2] - wy[fs + k];
            const double norm = geometry::sqrt_ieee(ex * ex + ey * ey);
            if (norm > EPS_LINE) {
                l.a = ey / norm;
                l.b = -ex / norm;
                l.c = -(l.a * wx[fs + k] + l.b * wy[fs + k]);
                l.found = true;
            }
        }
        ++k;
    }
    return l;
}

// Which side of the line a polygon lies on as a whole: -1 (+1) if clip_split would leave it
// all on side A (B), its vertices copied in order, the flags of edges lying on the line
// raised (as clip_split settles them) and nothing on the other side; 0 if clip_split must
// cut it. That is every vertex on that side or within EPS_LINE of the line (geometry::side),
// and fewer than three on the line (three would make the other side a part of their own).
// The flags are raised here, in place: the polygon's record then stands for the copy, with
// the same vertices and so the same area, bit for bit.
inline int whole_side(const double* wx, const double* wy, uint8_t* wf, int64_t start, int64_t n, double a, double b,
                      double c, double* d) {
    const auto [lo, hi] = linear_range(wx, wy, start, n, a, b, c, d);  // d: kept for split_by_distances
    if (hi < -EPS_LINE) return -1;
    if (lo > EPS_LINE) return 1;
    const int keep = hi <= EPS_LINE ? -1 : (lo >= -EPS_LINE ? 1 : 0);
    if (keep == 0) return 0;
    // on the line: geometry::side 0
    auto on = [&](int64_t k) { return std::fabs(d[k]) <= EPS_LINE; };
    int64_t on_line = 0;
    for (int64_t k = 0; k < n; ++k) on_line += on(k);
    if (on_line >= 3) return 0;
    if (on_line == 2)
        for (int64_t k = 0; k < n; ++k)
            if (on(k) && on(k + 1 < n ? k + 1 : 0)) wf[start + k] = 1;  // an edge on the line
    return keep;
}

// Resolve the polygon list recs[0 .. n_init) (front to back, background last). Vertices from
// n_vert on are free. Writes the records of the visible pieces to W.visible and returns their
// count, or -1 if a buffer was too small (the caller grows the workspace and calls again).
inline int64_t integrate_pixel(PixelWork& W, int64_t n_init, int64_t n_vert, const double* planes, double eps_z) {
    double* wx = W.v.x.data();
    double* wy = W.v.y.data();
    uint8_t* wf = W.v.f.data();
    const int64_t wcap = W.v.size();
    Rows<int64_t, 3>& recs = W.recs;
    int64_t* litems = W.items.data();
    const int64_t items_cap = int64_t(W.items.size());
    Rows<int64_t, 2>& lists = W.lists;
    int64_t* stack = W.stack.data();
    const int64_t stack_cap = int64_t(W.stack.size());
    int64_t n_poly = n_init;
    for (int64_t j = 0; j < n_init; ++j) litems[j] = j;
    int64_t n_items = n_init;
    lists[0][0] = 0;
    lists[0][1] = n_init;
    int64_t n_lists = 1;
    stack[0] = 0;
    int64_t top = 1, n_out = 0, steps = 0;
    int64_t moved_list = -1;  // the list whose front was just replaced, and how many times in a row
    int64_t moves = 0;
    while (top > 0 && steps < MAX_STEPS) {
        ++steps;
        --top;
        const int64_t L = stack[top];
        const int64_t s0 = lists[L][0];
        const int64_t cnt = lists[L][1];
        if (L != moved_list) {
            moved_list = -1;
            moves = 0;
        }
        const int64_t f = litems[s0];
        const int64_t src_f = recs[f][2];
        // 2. the first unclipped (and not degenerate) edge of the front polygon
        Line line{false, 0.0, 0.0, 0.0};
        if (cnt > 1) line = first_clip_edge(wx, wy, wf, recs[f][0], recs[f][1]);
        bool clip = line.found;
        double a = line.a, b = line.b, c = line.c;
        if (cnt > 1 && !clip && is_sliver(W.areas, litems, s0, cnt)) {
            // F has no edge left to clip along, so it should be the whole region; smaller, it
            // is a rounding remnant: dropped, and the list looked at again
            for (int64_t i = 0; i < cnt - 1; ++i) litems[s0 + i] = litems[s0 + i + 1];
            lists[L][1] = cnt - 1;
            stack[top] = L;
            ++top;
            moved_list = -1;
            continue;
        }
        if (cnt > 1 && !clip && moves >= cnt) {
            // more fronts than members: the move-to-front went round a cycle that only the
            // shared-plane tolerance closes (depth ties are not transitive); every polygon of
            // the cycle is within a few eps_z of the others here, so F stays in front
        } else if (cnt > 1 && !clip) {
            // F is clipped on all sides, so it covers its list's region: check depth
            int64_t front = -1;
            for (int64_t i = 1; i < cnt; ++i) {
                const int64_t q = litems[s0 + i];
                const int64_t sq = recs[q][2];
                if (sq == BACKGROUND) continue;
                const int rel = depth_relation(planes, sq, src_f, wx, wy, recs[q][0], recs[q][1], eps_z);
                if (rel == 1) {
                    front = i;
                    break;
                }
                if (rel == 2) {
                    // q crosses F's depth plane: split along the line z_q = z_F
                    const double da = planes[3 * sq] - planes[3 * src_f];
                    const double db = planes[3 * sq + 1] - planes[3 * src_f + 1];
                    const double norm = geometry::sqrt_ieee(da * da + db * db);
                    a = da / norm;
                    b = db / norm;
                    c = (planes[3 * sq + 2] - planes[3 * src_f + 2]) / norm;
                    clip = true;
                    break;
                }
            }
            if (front > 0) {
                // the nearer polygon moves to the front and the list is looked at again
                const int64_t q = litems[s0 + front];
                for (int64_t i = front; i > 0; --i) litems[s0 + i] = litems[s0 + i - 1];
                litems[s0] = q;
                stack[top] = L;
                ++top;
                moved_list = L;
                ++moves;
                continue;
            }
        }
        if (!clip) {
            // 2. the front polygon is visible over this whole region
            if (n_out >= int64_t(W.visible.size())) return -1;
            W.visible[size_t(n_out)] = f;
            ++n_out;
            continue;
        }
        // 3. clip every polygon in the list against the line into two lists
        if (n_lists + 2 > lists.rows() || top + 2 > stack_cap || n_items + 2 * cnt > items_cap ||
            n_poly + 2 * cnt > recs.rows())
            return -1;
        const int64_t a_start = n_items;
        const int64_t b_start = n_items + cnt;
        int64_t a_cnt = 0, b_cnt = 0;
        for (int64_t i = 0; i < cnt; ++i) {
            const int64_t p = litems[s0 + i];
            const int64_t n = recs[p][1];
            // a polygon on one side goes to that list as it is (whole_side raises the flags
            // clip_split would give its copy)
            if (n > int64_t(W.dist.size())) grow(W.dist, n);
            double* dist = W.dist.data();
            const int one_side = whole_side(wx, wy, wf, recs[p][0], n, a, b, c, dist);
            if (one_side != 0) {
                if (W.areas[size_t(p)] > AREA_EMPTY) {
                    if (one_side < 0)
                        litems[a_start + a_cnt++] = p;
                    else
                        litems[b_start + b_cnt++] = p;
                }
                continue;
            }
            const int64_t at_b = n_vert + 2 * n + 2;  // a half-plane clip at most doubles the vertices
            if (at_b + 2 * n + 2 > wcap) return -1;
            // (the distances whole_side computed: clip_split's own, so its outputs bit for bit)
            const geometry::SplitCounts m =
                split_by_distances(wx, wy, wf, recs[p][0], n, dist, a, b, c, wx, wy, wf, n_vert, at_b);
            const int64_t src_p = recs[p][2];
            double area_a = 0.0;
            if (m.a > 0) area_a = geometry::signed_area(wx, wy, n_vert, m.a);
            if (area_a > AREA_EMPTY) {
                litems[a_start + a_cnt] = n_poly;
                ++a_cnt;
                W.areas[size_t(n_poly)] = area_a;
                n_poly = record(recs, n_poly, n_vert, m.a, src_p);
            }
            double area_b = 0.0;
            if (m.b > 0) area_b = geometry::signed_area(wx, wy, at_b, m.b);
            if (area_b > AREA_EMPTY) {
                litems[b_start + b_cnt] = n_poly;
                ++b_cnt;
                W.areas[size_t(n_poly)] = area_b;
                n_poly = record(recs, n_poly, at_b, m.b, src_p);
            }
            n_vert = at_b + m.b;
        }
        n_items += 2 * cnt;
        // 4. reenter the algorithm for each of the two lists
        const int64_t starts[2] = {a_start, b_start};
        const int64_t counts[2] = {a_cnt, b_cnt};
        for (int h = 0; h < 2; ++h) {
            if (counts[h] > 0) {
                lists[n_lists][0] = starts[h];
                lists[n_lists][1] = counts[h];
                stack[top] = n_lists;
                ++top;
                ++n_lists;
            }
        }
    }
    return n_out;
}

// pixel_polygons then integrate_pixel: the count of visible pieces (records W.visible[:count])
// or -1 if the workspace is too small.
inline int64_t integrate_visible(const Strip& S, const int64_t* plist, int64_t n_pl, int64_t solid, double x0,
                                 double y0, const double* planes, double eps_z, PixelWork& W) {
    const PolygonsUsed pu = pixel_polygons(S, plist, n_pl, solid, x0, y0, W);
    int64_t n_out = -1;
    if (pu.used >= 0) n_out = integrate_pixel(W, pu.n_rec, pu.used, planes, eps_z);
    return n_out;
}

// Run the pixel integrator (growing its workspace until it fits) and emit every visible piece
// with its vertices, in the order the integrator found them.
template <class Sink>
inline void integrate(const Strip& S, const int64_t* plist, int64_t n_pl, int64_t solid, double x0, double y0,
                      const double* planes, double eps_z, int64_t pix, PixelWork& W, Sink& out) {
    int64_t n_out = integrate_visible(S, plist, n_pl, solid, x0, y0, planes, eps_z, W);
    while (n_out < 0) {
        W.grow_all();
        n_out = integrate_visible(S, plist, n_pl, solid, x0, y0, planes, eps_z, W);
    }
    for (int64_t o = 0; o < n_out; ++o) {
        const int64_t* r = W.recs[W.visible[size_t(o)]];
        out.emit_piece(pix, r[2], W.v.x.data(), W.v.y.data(), r[0], r[1]);
    }
}

}  // namespace aaeval::catmull
