// The hidden-surface loop: pieces live in an arena (pools of vertices, labels, contour
// starts; per piece its ranges, source polygon and box) and are referred to by index. The
// paper's recursion (solve the inside list again with an offending polygon as the clip
// polygon) is a stack of tasks, each a list of piece indices and the stack of clip
// polygons still being processed; taking the newest task first visits them in the order
// the recursion would.
#include "solver.hpp"

#include <algorithm>
#include <cmath>

#include "clipper.hpp"
#include "arena.hpp"
#include "convex_road.hpp"
#include "depth.hpp"
#include "holed_outline.hpp"
#include "local_outline.hpp"

namespace wa {

namespace {

bool disjoint(const Box& p, const Box& b) { return p.x0 >= b.x1 || p.x1 <= b.x0 || p.y0 >= b.y1 || p.y1 <= b.y0; }

bool within(const Box& bb, const std::array<double, 4>& win) {
    return bb.x0 >= win[0] && bb.x1 <= win[2] && bb.y0 >= win[1] && bb.y1 <= win[3];
}

// Whether shape a holds the same contours as b, bit for bit.
bool same_shape(const Shape& a, const ShapeView& b) {
    return (i64)a.x.size() == b.n && (i64)a.st.size() == b.nst && std::equal(a.st.begin(), a.st.end(), b.st) &&
           std::equal(a.x.begin(), a.x.end(), b.x) && std::equal(a.y.begin(), a.y.end(), b.y) &&
           std::equal(a.lab.begin(), a.lab.end(), b.lab);
}

// Piece pid (its box meeting the outline's box) split by an outline, its parts appended
// to the inside and outside lists.
// keep_inside false: the part inside is not stored (a piece wholly behind the outline's
// polygon, whose inside part step c would drop), only the outside part.
void clip_piece(Arena& arena, i64 pid, bool convex, const Outline& o, double eps, bool convex_road, Work& w,
                std::vector<i64>& inside, std::vector<i64>& outside, bool keep_inside = true) {
    i64 source = arena.source(pid);
    ShapeView s = arena.piece(pid);
    // No clip edge near the piece's box: the outline's boundary does not pass through
    // the box, so the piece lies wholly inside or wholly outside it, as the winding
    // number of any one of its points says. The clipper would find the same (its
    // step 2) after sorting every vertex of both. (Asked first: it costs a look at
    // the outline's chunks, where separation tests every edge.)
    const Box& sb = arena.box[pid];
    Box grown{sb.x0 - RIM * eps, sb.y0 - RIM * eps, sb.x1 + RIM * eps, sb.y1 + RIM * eps};
    if (!local_outline(o, grown, w.local)) {
        (contour_inside(s, 0, o) ? inside : outside).push_back(pid);
        return;
    }
    // Separation is asked only of a piece the convex road would cut: any other piece the
    // clip below hands on whole when it lies to one side, and pieces with an outline edge
    // near them mostly straddle it, so a test of every edge would mostly be spent for nothing.
    if (convex && convex_road && is_convex_piece(s)) {
        int side =
            separation(s.x, s.y, s.n, o.x.data(), o.y.data(), (i64)o.x.size(), eps, o.len.data(), &arena.box[pid]);
        if (side == OUTSIDE) outside.push_back(pid);
        else if (side == INSIDE) inside.push_back(pid);
        else cut_by_outline(arena, pid, source, o, eps, w, inside, outside);
        return;
    }
    const Outline& clip = w.local;
    bool parts_clean = clip_into(s, clip.view(), eps, w.in, w.out, w.clip, w.is_clean(arena, pid, eps), keep_inside,
                                 clip.clean ? clip.own.data() : nullptr, &arena.box[pid]);
    // A clip that holds the piece whole on one side (the boundaries apart: the clipper's
    // step 2) hands on the piece itself, not a copy.
    if (w.in.st.size() <= 1 || w.out.st.size() <= 1) {
        bool in = w.in.st.size() > 1;
        if (same_shape(in ? w.in : w.out, s)) {
            if (in && keep_inside) inside.push_back(pid);
            else if (!in) outside.push_back(pid);
            return;
        }
    }
    if (w.in.st.size() > 1 && keep_inside) inside.push_back(w.store(arena, w.in, source, parts_clean));
    if (w.out.st.size() > 1) outside.push_back(w.store(arena, w.out, source, parts_clean));
}

Outline outline_of(const double* ox, const double* oy, const i64* ost, i64 src) {
    i64 a = ost[src], b = ost[src + 1];
    Outline o;
    o.x.assign(ox + a, ox + b);
    o.y.assign(oy + a, oy + b);
    o.lab.assign(b - a, EDGE_CUT);
    o.st = {0, b - a};
    o.len.resize(b - a);
    for (i64 i = 0; i < b - a; ++i) {
        i64 j = i + 1 < b - a ? i + 1 : 0;
        o.len[i] = std::hypot(o.x[j] - o.x[i], o.y[j] - o.y[i]);
    }
    return o;
}

Box box_of(const double* obb, i64 s) { return Box{obb[4 * s], obb[4 * s + 1], obb[4 * s + 2], obb[4 * s + 3]}; }

struct Solver {
    Arena arena;
    const double *ox, *oy;
    const i64* ost;
    const double *obb, *planes;
    double eps, eps_z;
    bool convex_road;
    Work work;
    std::vector<i64> visible;
    std::vector<std::vector<i64>> task_ids, task_stack;

    // The task's pieces split by polygon src's original outline: (inside, outside).
    void clip_list(const std::vector<i64>& ids, i64 src, const Outline& o, std::vector<i64>& inside,
                   std::vector<i64>& outside) {
        Box box = box_of(obb, src);
        bool convex = is_convex(o.x.data(), o.y.data(), (i64)o.x.size());
        for (i64 pid : ids) {
            if (arena.source(pid) == src) inside.push_back(pid);  // a piece always lies in its own outline
            else if (disjoint(arena.box[pid], box)) outside.push_back(pid);
            else clip_piece(arena, pid, convex, o, eps, convex_road, work, inside, outside);
        }
    }

    // Step c: inside pieces behind polygon src dropped, those crossing its plane split
    // along the crossing line: (kept pieces, pieces of other polygons in front).
    void resolve_inside(i64 src, const std::vector<i64>& inside, std::vector<i64>& kept, std::vector<i64>& offenders) {
        for (i64 pid : inside) {
            i64 source = arena.source(pid);
            if (source == src) {
                kept.push_back(pid);
                continue;
            }
            ShapeView s = arena.piece(pid);
            int rel = relation(s, source, src, planes, eps_z);
            double a = planes[3 * source] - planes[3 * src];
            double b = planes[3 * source + 1] - planes[3 * src + 1];
            double c = planes[3 * source + 2] - planes[3 * src + 2];
            if (rel == FRONT) {
                kept.push_back(pid);
                offenders.push_back(pid);
            } else if (rel == 0 && convex_road && takes_convex_road(s)) {
                i64 f = cut_by_plane_line(arena, pid, source, a, b, c, eps, work);
                if (f >= 0) {
                    kept.push_back(f);
                    offenders.push_back(f);
                }
            } else if (rel == 0) {
                Shape h = half_plane(a, b, c, arena.box[pid]);
                Shape f = clip_arrays(s, h.view(), eps).first;
                if (f.st.size() > 1) {
                    i64 k = arena.add(f, source);
                    kept.push_back(k);
                    offenders.push_back(k);
                }
            }
        }
    }

    // Steps c and d for the inside list of polygon src: the visible pieces appended, or
    // the list pushed as a task with its first offender as the clip polygon.
    void settle(i64 src, const std::vector<i64>& inside, const std::vector<i64>& stack) {
        std::vector<i64> kept, offenders;
        resolve_inside(src, inside, kept, offenders);
        i64 first = -1;
        for (i64 pid : offenders) {
            i64 s = arena.source(pid);
            if (std::find(stack.begin(), stack.end(), s) == stack.end()) {
                first = pid;
                break;
            }
        }
        if (first < 0) {
            // no offender, or only polygons on the stack (cyclic overlap): all that lay
            // behind them is gone already, so what is left does not overlap
            visible.insert(visible.end(), kept.begin(), kept.end());
            return;
        }
        std::vector<i64> again{first};
        for (i64 pid : kept)
            if (pid != first) again.push_back(pid);
        std::vector<i64> deeper(stack);
        deeper.push_back(src);
        task_ids.push_back(std::move(again));
        task_stack.push_back(std::move(deeper));
    }

    // Solve the stacked tasks (an inside list and what it spawns) to the end.
    void run_tasks() {
        while (!task_ids.empty()) {
            std::vector<i64> ids = std::move(task_ids.back());
            std::vector<i64> stack = std::move(task_stack.back());
            task_ids.pop_back();
            task_stack.pop_back();
            if (ids.empty()) continue;
            i64 src = arena.source(ids[0]);
            Outline o = outline_of(ox, oy, ost, src);
            std::vector<i64> inside, outside;
            clip_list(ids, src, o, inside, outside);
            // the rest of this list after the inside list (pushed first: taken last)
            task_ids.push_back(std::move(outside));
            task_stack.push_back(stack);
            settle(src, inside, stack);
        }
    }

    // Piece pid, or if it has over SPLIT_VERTICES vertices its halves across the middle
    // of its box's longer side, and so on (appended to out). Behind many small polygons a
    // large piece (a background) becomes one polygon with a hole for each, and every later
    // clip there took in all of it; halved, a clip meets only the halves under it. The
    // paper's screen subdivision, piece by piece; cut edges are EDGE_CUT, as window borders.
    void halve(i64 pid, std::vector<i64>& out) {
        ShapeView s = arena.piece(pid);
        Box b = arena.box[pid];
        if (s.n <= SPLIT_VERTICES || (b.x1 - b.x0 <= 1.0 && b.y1 - b.y0 <= 1.0)) {
            out.push_back(pid);
            return;
        }
        double x0 = b.x0 - 1, y0 = b.y0 - 1, x1 = b.x1 + 1, y1 = b.y1 + 1;
        if (b.x1 - b.x0 >= b.y1 - b.y0) x1 = std::floor(0.5 * (b.x0 + b.x1));
        else y1 = std::floor(0.5 * (b.y0 + b.y1));
        const double hx[4] = {x0, x1, x1, x0}, hy[4] = {y0, y0, y1, y1};
        const i64 hl[4] = {EDGE_CUT, EDGE_CUT, EDGE_CUT, EDGE_CUT}, hs[2] = {0, 4};
        Shape &a = work.in, &c = work.out;  // free again once both are stored, before the recursion
        bool parts_clean = clip_into(s, ShapeView{hx, hy, hl, hs, 4, 2}, eps, a, c, work.clip,
                                     work.is_clean(arena, pid, eps), true, nullptr, &b);
        i64 source = arena.source(pid);
        if (a.st.size() < 2 || c.st.size() < 2) return out.push_back(pid);  // the line missed it
        i64 ka = work.store(arena, a, source, parts_clean), kc = work.store(arena, c, source, parts_clean);
        halve(ka, out);
        halve(kc, out);
    }

    // Indices of the visible pieces (they do not overlap), appended to `visible`. The live
    // pieces of later polygons are found through a grid of buckets over the window: a clip
    // polygon meets only the pieces in the buckets its box covers, where walking every
    // overlapping polygon's pieces would cost each clip a look at all of them (a large
    // polygon behind many small ones, a background, ends up in thousands of pieces: a walk
    // that grows with the square of the scene). The pieces a clip polygon meets are taken
    // in depth order of their polygons, then in the order they were made (arena index): a
    // deterministic order that does not depend on the grid.
    void solve(const std::vector<i64>& first, const i64* order, i64 n, i64 npoly,
                       const std::array<double, 4>& win, const i64* group) {
        std::vector<i64> position(npoly, -1);
        for (i64 p = 0; p < n; ++p) position[order[p]] = p;
        // per piece: its polygon's depth position while it waits (-1 once taken), the last
        // clip polygon that saw it (met once though in many buckets), and the polygon with
        // holes (group) it is known to lie outside of (-1: none)
        std::vector<i64> pos, stamp, cleared;
        auto grow = [&]() {
            if ((i64)pos.size() < arena.size()) {
                pos.resize(arena.size(), -1);
                stamp.resize(arena.size(), -1);
                cleared.resize(arena.size(), -1);
            }
        };
        HoledOutlines holed(ox, oy, ost, group, npoly, eps);
        // about two pieces' boxes a bucket at the start, at most 256 a side
        double w = std::max(win[2] - win[0], 1e-300), h = std::max(win[3] - win[1], 1e-300);
        double side = std::sqrt(std::max<double>(1.0, (double)first.size() / 2.0) * std::max(w, h) / std::min(w, h));
        i64 gx = std::clamp<i64>((i64)std::ceil(side * (w >= h ? 1.0 : w / h)), 1, 256);
        i64 gy = std::clamp<i64>((i64)std::ceil(side * (h >= w ? 1.0 : h / w)), 1, 256);
        double cw = w / (double)gx, ch = h / (double)gy;
        std::vector<std::vector<i64>> cells(gx * gy);
        auto span = [&](const Box& b, i64& i0, i64& i1, i64& j0, i64& j1) {
            i0 = std::clamp<i64>((i64)std::floor((b.x0 - win[0]) / cw), 0, gx - 1);
            i1 = std::clamp<i64>((i64)std::floor((b.x1 - win[0]) / cw), 0, gx - 1);
            j0 = std::clamp<i64>((i64)std::floor((b.y0 - win[1]) / ch), 0, gy - 1);
            j1 = std::clamp<i64>((i64)std::floor((b.y1 - win[1]) / ch), 0, gy - 1);
        };
        auto enter = [&](i64 pid, i64 p) {
            grow();
            pos[pid] = p;
            i64 i0, i1, j0, j1;
            span(arena.box[pid], i0, i1, j0, j1);
            for (i64 j = j0; j <= j1; ++j)
                for (i64 i = i0; i <= i1; ++i) cells[j * gx + i].push_back(pid);
        };
        for (i64 pid : first) enter(pid, position[arena.source(pid)]);
        std::vector<i64> inside, parts, met, halves, dropped;
        const std::vector<i64> empty;
        // a polygon's first piece when it is its whole outline (inside the window): the two
        // are self_clean together (self_clean reads no labels), so one check does for both
        std::vector<i64> whole_piece(npoly, -1);
        for (i64 pid : first)
            if (within(box_of(obb, arena.source(pid)), win)) whole_piece[arena.source(pid)] = pid;
        // per group of a polygon with holes: whether its parts' planes are one (bit for bit)
        std::vector<signed char> one_plane(npoly, -1);
        auto same_plane = [&](i64 g) {
            if (one_plane[g] < 0) {
                one_plane[g] = 1;
                for (i64 q : holed.parts[g])
                    for (int c = 0; c < 3; ++c)
                        if (planes[3 * q + c] != planes[3 * holed.parts[g][0] + c]) one_plane[g] = 0;
            }
            return one_plane[g] > 0;
        };
        for (i64 p = 0; p < n; ++p) {
            i64 src = order[p];
            Box box = box_of(obb, src);
            met.clear();
            i64 i0, i1, j0, j1;
            span(box, i0, i1, j0, j1);
            for (i64 j = j0; j <= j1; ++j)
                for (i64 i = i0; i <= i1; ++i) {
                    std::vector<i64>& cell = cells[j * gx + i];
                    size_t keep = 0;
                    for (i64 pid : cell) {
                        if (pos[pid] < p) continue;  // taken or cut up: dropped from the bucket
                        cell[keep++] = pid;
                        if (stamp[pid] == p) continue;
                        stamp[pid] = p;
                        if (pos[pid] == p) met.push_back(pid);
                        // pieces of one polygon cut into convex parts (one group) abut, never overlap
                        else if (!disjoint(arena.box[pid], box) && (!group || group[arena.source(pid)] != group[src]))
                            met.push_back(pid);
                    }
                    cell.resize(keep);
                }
            std::sort(met.begin(), met.end(), [&](i64 a, i64 b) { return pos[a] != pos[b] ? pos[a] < pos[b] : a < b; });
            inside.clear();
            size_t k = 0;
            for (; k < met.size() && pos[met[k]] == p; ++k) {
                inside.push_back(met[k]);
                pos[met[k]] = -1;
            }
            if (inside.empty()) continue;  // nothing of this polygon is left in the window
            Outline o = outline_of(ox, oy, ost, src);
            bool convex = is_convex(o.x.data(), o.y.data(), (i64)o.x.size());
            i64 wp = whole_piece[src];
            o.clean = wp >= 0 ? work.is_clean(arena, wp, eps) : self_clean(o.view(), eps, work.clip);
            index_chunks(o);
            i64 g = holed.holed_group(src);
            for (; k < met.size(); ++k) {
                i64 pid = met[k], q = pos[pid];
                parts.clear();
                // a piece wholly behind a part of a polygon with holes lies behind all of
                // it (one plane): clipped by the whole polygon once, skipped by its other
                // parts (a piece cut from one so clipped lies outside the whole polygon)
                if (g >= 0 && cleared[pid] == g && same_plane(g)) continue;
                bool behind = wholly_behind(arena.piece(pid), arena.source(pid), src, planes, eps_z);
                bool whole = behind && g >= 0;
                if (whole && cleared[pid] == g) continue;
                dropped.clear();
                clip_piece(arena, pid, convex && !whole, whole ? holed.of(g) : o, eps, convex_road, work,
                           behind ? dropped : inside, parts, !behind);
                i64 mark = whole ? g : cleared[pid];
                if (parts.size() == 1 && parts[0] == pid) {  // wholly outside: it stays
                    cleared[pid] = mark;
                    continue;
                }
                pos[pid] = -1;
                for (i64 part : parts) {
                    halves.clear();
                    halve(part, halves);
                    for (i64 h : halves) {
                        enter(h, q);
                        cleared[h] = mark;
                    }
                }
            }
            settle(src, inside, empty);
            run_tasks();
        }
    }
};

}  // namespace

Visible solve_window(const double* ox, const double* oy, const i64* ost, i64 npoly, const double* obb,
                     const double* planes, const i64* order, i64 norder, const std::array<double, 4>& win,
                     double eps, double eps_z, bool convex_road, const i64* group) {
    Solver S;
    // the pieces of a tiger-like illustration hold about ten times the input's vertices,
    // in about six pieces a polygon: reserved at once, the pools are not copied a dozen
    // times over while they grow by doubling, onto fresh pages each time
    S.arena.reserve(16 * ost[npoly] + 1024, 8 * norder + 128);
    S.ox = ox;
    S.oy = oy;
    S.ost = ost;
    S.obb = obb;
    S.planes = planes;
    S.eps = eps;
    S.eps_z = eps_z;
    S.convex_road = convex_road;
    // each polygon (in depth order) clipped to the window, its edges labelled EDGE_OWN
    const double wxs[4] = {win[0], win[2], win[2], win[0]}, wys[4] = {win[1], win[1], win[3], win[3]};
    const i64 wl[4] = {EDGE_CUT, EDGE_CUT, EDGE_CUT, EDGE_CUT}, ws[2] = {0, 4};
    ShapeView window{wxs, wys, wl, ws, 4, 2};
    // (a self-clean polygon takes the clipper's clean road: the same bits, sooner)
    std::vector<i64> first;
    Shape piece, outside;
    for (i64 k = 0; k < norder; ++k) {
        i64 s = order[k], a = ost[s], b = ost[s + 1];
        piece.x.assign(ox + a, ox + b);
        piece.y.assign(oy + a, oy + b);
        piece.lab.assign(b - a, EDGE_OWN);
        piece.st = {0, b - a};
        bool clean = false;
        if (!within(box_of(obb, s), win)) {
            Shape whole = piece;
            clean = clip_into(whole.view(), window, eps, piece, outside, S.work.clip,
                              self_clean(whole.view(), eps, S.work.clip));
        }
        if (piece.st.size() > 1) first.push_back(S.work.store(S.arena, piece, s, clean));
    }
    S.solve(first, order, norder, npoly, win, group);
    // the visible pieces flattened
    Visible out;
    const Arena& A = S.arena;
    out.piece_rings.push_back(0);
    out.starts.reserve(S.visible.size() + 1);
    for (i64 pid : S.visible) {
        const Arena::Meta& m = A.meta[pid];
        i64 v = (i64)out.xs.size();
        out.sources.push_back(m.source);
        out.xs.insert(out.xs.end(), A.x.begin() + m.v0, A.x.begin() + m.v1);
        out.ys.insert(out.ys.end(), A.y.begin() + m.v0, A.y.begin() + m.v1);
        out.labels.insert(out.labels.end(), A.lab.begin() + m.v0, A.lab.begin() + m.v1);
        for (i64 j = m.r0; j + 1 < m.r1; ++j) out.starts.push_back(v + A.st[j]);
        out.piece_rings.push_back((i64)out.starts.size());
    }
    out.starts.push_back((i64)out.xs.size());
    return out;
}

}  // namespace wa
