/* voronoi.cc - Voronoi tissues from CGAL's Delaunay triangulation.
 *
 * CGAL's periodic triangulation (5.5) takes square domains only, so the
 * periodic triangulation is read off a plain Delaunay triangulation of the
 * seeds and of their periodic copies within a margin around the box.  A
 * triangle of that triangulation is a true periodic Delaunay triangle when
 * its circumcircle lies inside the region the copies cover: then every
 * periodic image that could fall inside the circle was there to be tested.
 * The margin starts at a few seed spacings and doubles until every triangle
 * around every seed of the central copy passes that test.
 *
 * Each periodic triangle appears once per copy; its "home" copy is the one
 * in which its lowest-numbered seed is the central copy.  Vertices are the
 * circumcenters of home triangles; the cell of seed s is the ccw cycle of
 * triangles around the central copy of s, each mapped to its home.
 *
 * Everything C++ stays in this file; the C boundary catches every exception.
 */
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/assertions_behaviour.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "voronoi.h"

extern "C" {
#include "range.h"  /* plain C, like mesh.h */
}

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;

/* A seed or one of its periodic copies: the seed plus (ia lx, ib ly). */
struct Copy {
	int seed, ia, ib;
	bool central() const { return ia == 0 && ib == 0; }
};

typedef CGAL::Triangulation_vertex_base_with_info_2<Copy, K> Vb;
/* Face info: -2 not next to a central seed (unused), -1 not yet numbered,
 * else the vertex id of the tissue. */
typedef CGAL::Triangulation_face_base_with_info_2<int, K> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Delaunay_triangulation_2<K, Tds> Dt;
typedef K::Point_2 Point;

/* mesh.c caps counts at INT_MAX/8 corners; a tissue has 6 corners per seed */
const int max_seeds = 10000000;

/* Initial margin in seed spacings: a Poisson-Delaunay circumradius exceeds 3
 * spacings with probability ~1e-11, so doubling is rare for random seeds. */
const double margin0 = 6.0;

/* A thrown failure; the message is already in the mesh_error. */
struct Failure {
	int status;
};

#define FAIL(err, status, ...) throw Failure{mesh_error_set((err), 0, (status), __VA_ARGS__)}

/* Run f, turning every exception into a status: nothing may unwind into C. */
void quiet_failure(const char *, const char *, const char *, int, const char *)
{
}

/* CGAL's default failure handler prints several lines to std::cerr before
 * it throws; for the time of f it is silenced (and put back after), so a
 * failure reaches the caller as one status and message. */
struct Quiet_cgal {
	CGAL::Failure_function old_error, old_warning;
	Quiet_cgal()
		: old_error(CGAL::set_error_handler(quiet_failure)),
		  old_warning(CGAL::set_warning_handler(quiet_failure)) {}
	~Quiet_cgal()
	{
		CGAL::set_error_handler(old_error);
		CGAL::set_warning_handler(old_warning);
	}
};

template <class F>
int guarded(mesh_error *err, F f)
{
	Quiet_cgal quiet;
	try {
		return f();
	} catch (const Failure &e) {
		return e.status;
	} catch (const std::bad_alloc &) {
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	} catch (const std::exception &e) {
		/* what() of a CGAL failure is several lines: keep the first */
		std::string w = e.what();
		return mesh_error_set(err, 0, MESH_EINVAL, "triangulation failed: %.120s",
		                      w.substr(0, w.find('\n')).c_str());
	} catch (...) {
		return mesh_error_set(err, 0, MESH_EINVAL, "triangulation failed");
	}
}

/* The binary grid that makes copies exact translates: multiples of q up to
 * 2^e are exact doubles, and every coordinate of a copy (a seed plus a few
 * box lengths) stays below 2^e = next power of two above 16 L. */
double grid_spacing(double l)
{
	int e;
	std::frexp(16.0 * l, &e);
	return std::ldexp(1.0, e - 52);
}

double snap(double x, double q)
{
	return std::nearbyint(x / q) * q;
}

/* x into [0, l) on the grid q (l itself on the grid, so the fix-ups are exact). */
double wrap_snap(double x, double l, double q)
{
	double w = snap(x - l * std::floor(x / l), q);
	if (w < 0)
		w += l;
	if (w >= l)
		w -= l;
	return w + 0.0; /* no negative zero */
}

double wrap(double x, double l)
{
	double w = x - l * std::floor(x / l);
	return (w >= l || w < 0) ? 0.0 : w;
}

struct Tessellation {
	double lx, ly;            /* box on the grid */
	double h;                 /* mean seed spacing */
	int n;
	std::vector<double> s;    /* 2n seeds, wrapped, on the grid */
	std::vector<double> rv;   /* 2nv vertices (circumcenters of home triangles) */
	std::vector<int> coff, cv;
	std::vector<double> cimg; /* 2 per corner: rv[cv[i]] + cimg[i] is next to the seed */
	std::vector<double> cdir; /* 2 per corner: unit direction of edge i -> i+1 */
	int nsplit = 0;
	int npoints = 0;

	int nv() const { return (int)rv.size() / 2; }
	double corner_x(int i) const { return rv[2 * cv[i]] + cimg[2 * i]; }
	double corner_y(int i) const { return rv[2 * cv[i] + 1] + cimg[2 * i + 1]; }
};

void check_input(double lx, double ly, int n, const double *xy, mesh_error *err)
{
	if (!(lx > 0 && ly > 0 && std::isfinite(lx) && std::isfinite(ly) &&
	      std::isfinite(lx * ly)))
		FAIL(err, MESH_EINVAL, "box must have positive finite sides");
	if (n < 3)
		FAIL(err, MESH_EINVAL, "too few seeds for a periodic triangulation (%d)", n);
	if (n > max_seeds)
		FAIL(err, MESH_EINVAL, "too many seeds (%d, at most %d)", n, max_seeds);
	for (int i = 0; i < 2 * n; i++)
		if (!std::isfinite(xy[i]))
			FAIL(err, MESH_EINVAL, "seed %d has a non-finite coordinate", i / 2);
	/* Fewer than about one seed across the box's short side: cells span
	 * it and border their own images, so there is no tissue, and the
	 * copies a margin of a few spacings needs grow as spacing/side (found
	 * by fuzz/seeds: 3 seeds in a 0.01 x 62 box took seconds). */
	double h = std::sqrt(lx * ly / n), side = std::min(lx, ly);
	if (side < 0.5 * h)
		FAIL(err, MESH_EINVAL, "too few seeds for a periodic triangulation of this box (the "
		     "seed spacing %.3g is more than twice the short side %.3g)", h, side);
}

void place_seeds(Tessellation &t, const double *xy, mesh_error *err)
{
	int n = t.n;
	double q = grid_spacing(std::max(t.lx, t.ly));
	t.lx = snap(t.lx, q);
	t.ly = snap(t.ly, q);
	t.h = std::sqrt(t.lx * t.ly / n);
	t.s.resize(2 * (size_t)n);
	for (int i = 0; i < n; i++) {
		t.s[2 * i] = wrap_snap(xy[2 * i], t.lx, q);
		t.s[2 * i + 1] = wrap_snap(xy[2 * i + 1], t.ly, q);
	}
	std::vector<int> order(n);
	for (int i = 0; i < n; i++)
		order[i] = i;
	const double *s = t.s.data();
	std::sort(order.begin(), order.end(), [s](int a, int b) {
		return s[2 * a] < s[2 * b] || (s[2 * a] == s[2 * b] && s[2 * a + 1] < s[2 * b + 1]);
	});
	for (int k = 1; k < n; k++) {
		int a = order[k - 1], b = order[k];
		if (s[2 * a] == s[2 * b] && s[2 * a + 1] == s[2 * b + 1]) {
			if (a > b)
				std::swap(a, b);
			FAIL(err, MESH_EINVAL, "seeds %d and %d coincide at (%.17g, %.17g) in the periodic box",
			     a, b, s[2 * a], s[2 * a + 1]);
		}
	}
}

/* Triangulate seeds and their copies within margin m.  Returns false if m
 * is too small for some triangle around a central seed. */
bool triangulate(Tessellation &t, double m, Dt &dt,
                 std::vector<Dt::Vertex_handle> &vh, mesh_error *err)
{
	int n = t.n;
	double lx = t.lx, ly = t.ly;
	int na = (int)std::ceil(m / lx), nb = (int)std::ceil(m / ly);
	size_t limit = std::max((size_t)64 * n, (size_t)1000000);
	std::vector<std::pair<Point, Copy>> pts;
	pts.reserve(n + n / 4);
	for (int a = -na; a <= na; a++)
		for (int b = -nb; b <= nb; b++) {
			for (int i = 0; i < n; i++) {
				double x = t.s[2 * i] + a * lx, y = t.s[2 * i + 1] + b * ly;
				if ((a == 0 && b == 0) ||
				    (x >= -m && x < lx + m && y >= -m && y < ly + m))
					pts.push_back(std::make_pair(Point(x, y), Copy{i, a, b}));
			}
			if (pts.size() > limit)
				FAIL(err, MESH_EINVAL, "too few seeds for a periodic triangulation of this box");
		}
	dt.clear();
	dt.insert(pts.begin(), pts.end());
	if (dt.number_of_vertices() != pts.size())
		FAIL(err, MESH_EINVAL, "seeds coincide in the periodic box");
	t.npoints = (int)pts.size();

	vh.assign(n, Dt::Vertex_handle());
	for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v)
		if (v->info().central())
			vh[v->info().seed] = v;

	/* Faces in storage order (not seed order) for memory locality.  The
	 * circle must stay clear of the margin's edge by more than the
	 * rounding of a circumcenter. */
	double eps = 1e-3 * t.h;
	int self = -1;
	for (auto f = dt.all_faces_begin(); f != dt.all_faces_end(); ++f) {
		f->info() = -2;
		bool near = false, inf = false;
		for (int j = 0; j < 3; j++) {
			if (dt.is_infinite(f->vertex(j)))
				inf = true;
			else if (f->vertex(j)->info().central())
				near = true;
		}
		if (!near)
			continue;
		if (inf)
			return false;
		f->info() = -1;
		const Point &p0 = f->vertex(0)->point();
		Point cc = CGAL::circumcenter(p0, f->vertex(1)->point(), f->vertex(2)->point());
		double r = std::sqrt(CGAL::squared_distance(cc, p0));
		if (!(cc.x() - r > -m + eps && cc.x() + r < lx + m - eps &&
		      cc.y() - r > -m + eps && cc.y() + r < ly + m - eps))
			return false;
		int s0 = f->vertex(0)->info().seed, s1 = f->vertex(1)->info().seed;
		int s2 = f->vertex(2)->info().seed;
		if (s0 == s1 || s0 == s2)
			self = s0;
		else if (s1 == s2)
			self = s1;
	}
	/* Only now, all circles checked, are these true periodic triangles;
	 * one using a seed twice (a cell next to its own image) is no tissue. */
	if (self >= 0)
		FAIL(err, MESH_EINVAL, "too few seeds for a periodic triangulation of this box "
		     "(seed %d borders its own periodic image)", self);
	return true;
}

/* The vertex of f with the lowest seed number. */
int lowest(Dt::Face_handle f)
{
	int k = 0;
	for (int j = 1; j < 3; j++)
		if (f->vertex(j)->info().seed < f->vertex(k)->info().seed)
			k = j;
	return k;
}

/* The vertex id of the home copy of f, whose lowest seed is the central
 * copy of seed e.seed: around that copy, the triangle with the same other
 * two seeds at the same relative images. */
int home_id(Dt::Face_handle f, int k, const std::vector<Dt::Vertex_handle> &vh)
{
	const Copy &e = f->vertex(k)->info();
	const Copy &e1 = f->vertex(Dt::ccw(k))->info(), &e2 = f->vertex(Dt::cw(k))->info();
	Dt::Vertex_handle u = vh[e.seed];
	Dt::Face_circulator g = u->incident_faces(), done(g);
	do {
		int kk = g->index(u);
		const Copy &g1 = g->vertex(Dt::ccw(kk))->info(), &g2 = g->vertex(Dt::cw(kk))->info();
		if (g1.seed == e1.seed && g1.ia == e1.ia - e.ia && g1.ib == e1.ib - e.ib &&
		    g2.seed == e2.seed && g2.ia == e2.ia - e.ia && g2.ib == e2.ib - e.ib)
			return g->info();
	} while (++g != done);
	return -1;
}

void build_cells(Tessellation &t, const Dt &dt, const std::vector<Dt::Vertex_handle> &vh,
                 mesh_error *err)
{
	int n = t.n;
	/* Home triangles get the vertex ids. */
	t.rv.clear();
	t.rv.reserve(4 * (size_t)n);
	for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
		if (f->info() == -2 || !f->vertex(lowest(f))->info().central())
			continue;
		f->info() = t.nv();
		Point cc = CGAL::circumcenter(f->vertex(0)->point(), f->vertex(1)->point(),
		                              f->vertex(2)->point());
		t.rv.push_back(cc.x());
		t.rv.push_back(cc.y());
	}
	if (t.nv() != 2 * n)
		FAIL(err, MESH_EINVAL, "inconsistent periodic triangulation (%d triangles for %d seeds)",
		     t.nv(), n);

	/* Cells, visited in storage order into a scratch list, then put in
	 * seed order. */
	struct Corner {
		int id;
		int ia, ib;
		double dx, dy;
	};
	std::vector<Corner> tmp;
	tmp.reserve(6 * (size_t)n);
	std::vector<int> start(n, -1), count(n, 0);
	for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
		if (!v->info().central())
			continue;
		int i = v->info().seed;
		start[i] = (int)tmp.size();
		Dt::Face_circulator f = v->incident_faces(), done(f);
		do {
			int k = lowest(f);
			const Copy &e = f->vertex(k)->info();
			int id = e.central() ? f->info() : home_id(f, k, vh);
			if (id < 0)
				FAIL(err, MESH_EINVAL, "inconsistent periodic triangulation around seed %d",
				     i);
			/* The next triangle ccw shares the edge v-w; the Voronoi
			 * edge dual to it runs along rot90(w - v). */
			Dt::Vertex_handle w = f->vertex(Dt::cw(f->index(v)));
			double dx = w->point().x() - v->point().x(), dy = w->point().y() - v->point().y();
			double d = std::sqrt(dx * dx + dy * dy);
			tmp.push_back(Corner{id, e.ia, e.ib, -dy / d, dx / d});
		} while (++f != done);
		count[i] = (int)tmp.size() - start[i];
	}
	if (tmp.size() != 6 * (size_t)n)
		FAIL(err, MESH_EINVAL, "inconsistent periodic triangulation (%zu corners for %d seeds)",
		     tmp.size(), n);
	t.coff.assign(n + 1, 0);
	t.cv.resize(tmp.size());
	t.cimg.resize(2 * tmp.size());
	t.cdir.resize(2 * tmp.size());
	for (int i = 0, o = 0; i < n; i++) {
		t.coff[i] = o;
		for (int c = 0; c < count[i]; c++, o++) {
			const Corner &q = tmp[start[i] + c];
			t.cv[o] = q.id;
			t.cimg[2 * o] = q.ia * t.lx;
			t.cimg[2 * o + 1] = q.ib * t.ly;
			t.cdir[2 * o] = q.dx;
			t.cdir[2 * o + 1] = q.dy;
		}
		t.coff[i + 1] = o;
	}
}

/* Give zero-length junctions (co-circular seeds) the length delta; see
 * voronoi.h for the rule. */
void split_degenerate(Tessellation &t, mesh_error *err)
{
	int n = t.n, nv = t.nv();
	double tol = 1e-9 * t.h, delta = 1e-3 * t.h;
	struct Edge {
		int a, b;
		double dx, dy;
	};
	std::vector<Edge> zero;
	std::vector<std::pair<int, int>> pairs;
	for (int k = 0; k < n; k++)
		for (int i = t.coff[k]; i < t.coff[k + 1]; i++) {
			int j = i + 1 < t.coff[k + 1] ? i + 1 : t.coff[k];
			double ex = t.corner_x(j) - t.corner_x(i), ey = t.corner_y(j) - t.corner_y(i);
			if (ex * ex + ey * ey >= tol * tol)
				continue;
			/* Both ways, so that a length at the tolerance, seen from
			 * one cell only, still links both ends. */
			int a = t.cv[i], b = t.cv[j];
			double dx = t.cdir[2 * i], dy = t.cdir[2 * i + 1];
			zero.push_back(Edge{a, b, dx, dy});
			zero.push_back(Edge{b, a, -dx, -dy});
			pairs.push_back(std::make_pair(std::min(a, b), std::max(a, b)));
		}
	std::sort(pairs.begin(), pairs.end());
	t.nsplit = (int)(std::unique(pairs.begin(), pairs.end()) - pairs.begin());
	if (zero.empty())
		return;

	std::vector<int> off(nv + 1, 0), adj(zero.size());
	for (const Edge &e : zero)
		off[e.a + 1]++;
	for (int v = 0; v < nv; v++)
		off[v + 1] += off[v];
	std::vector<int> fill(off.begin(), off.end() - 1);
	for (size_t z = 0; z < zero.size(); z++)
		adj[fill[zero[z].a]++] = (int)z;

	std::vector<double> shift(2 * (size_t)nv, 0.0);
	std::vector<char> seen(nv, 0);
	std::vector<int> queue;
	for (int root = 0; root < nv; root++) {
		if (seen[root] || off[root] == off[root + 1])
			continue;
		seen[root] = 1;
		queue.assign(1, root);
		for (size_t qi = 0; qi < queue.size(); qi++) {
			int a = queue[qi];
			for (int z = off[a]; z < off[a + 1]; z++) {
				const Edge &e = zero[adj[z]];
				if (seen[e.b])
					continue;
				seen[e.b] = 1;
				shift[2 * e.b] = shift[2 * a] + delta * e.dx;
				shift[2 * e.b + 1] = shift[2 * a + 1] + delta * e.dy;
				queue.push_back(e.b);
			}
		}
	}
	for (int i = 0; i < 2 * nv; i++)
		t.rv[i] += shift[i];

	/* Zero junctions of exactly co-circular seeds form trees (a cycle
	 * would enclose a seed with an empty cell); only input degenerate
	 * within the tolerance in some other way could make a cycle. */
	for (const Edge &e : zero) {
		double sx = shift[2 * e.b] - shift[2 * e.a], sy = shift[2 * e.b + 1] - shift[2 * e.a + 1];
		if (sx * e.dx + sy * e.dy < 0.5 * delta)
			FAIL(err, MESH_EINVAL, "seeds too degenerate: a Voronoi vertex of degree > 3 "
			     "could not be split");
	}
}

void tessellate(double lx, double ly, int n, const double *xy, Tessellation &t, mesh_error *err)
{
	check_input(lx, ly, n, xy, err);
	t.lx = lx;
	t.ly = ly;
	t.n = n;
	place_seeds(t, xy, err);

	Dt dt;
	std::vector<Dt::Vertex_handle> vh;
	/* Every point is within half the box diagonal of some copy of any
	 * seed, so no empty circle is wider than that and mmax always does. */
	double mmax = 2.0 * std::max(t.lx, t.ly) + margin0 * t.h;
	for (double m = margin0 * t.h;; m = std::min(2 * m, mmax)) {
		if (triangulate(t, m, dt, vh, err))
			break;
		if (m >= mmax)
			FAIL(err, MESH_EINVAL, "too few seeds for a periodic triangulation of this box");
	}
	build_cells(t, dt, vh, err);
	split_degenerate(t, err);
}

} /* namespace */

extern "C" int voronoi_seeds_random(unsigned long seed, double lx, double ly, int n,
                                    double *xy, mesh_error *err)
{
	if (range_box(lx, ly, err) != MESH_OK)
		return MESH_EINVAL;
	if (n < 0)
		return mesh_error_set(err, 0, MESH_EINVAL, "negative number of seeds");
	/* A gsl_rng on the stack: gsl_rng_alloc would call GSL's error
	 * handler, which aborts, when out of memory. */
	gsl_rng r;
	r.type = gsl_rng_mt19937;
	r.state = std::malloc(r.type->size);
	if (r.state == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	gsl_rng_set(&r, seed);
	for (int i = 0; i < n; i++) {
		/* u * l can round up to l: wrap keeps the half-open box */
		xy[2 * i] = wrap(gsl_rng_uniform(&r) * lx, lx);
		xy[2 * i + 1] = wrap(gsl_rng_uniform(&r) * ly, ly);
	}
	std::free(r.state);
	return MESH_OK;
}

extern "C" int voronoi_seeds_read(FILE *f, double **xy, int *n, mesh_error *err)
{
	*xy = NULL;
	*n = 0;
	char *line = NULL;
	size_t cap = 0, size = 0, len = 0;
	double *v = NULL;
	long lineno = 0;
	int st = MESH_OK;
	while ((len = getline(&line, &cap, f)) != (size_t)-1) {
		lineno++;
		const char *p = line;
		while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
			p++;
		if (*p == '\0' || *p == '#')
			continue;
		char *end;
		double x = std::strtod(p, &end);
		bool good = end != p;
		p = end;
		double y = std::strtod(p, &end);
		good = good && end != p && std::isfinite(x) && std::isfinite(y);
		p = end;
		while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
			p++;
		if (!good || *p != '\0' || std::strlen(line) != len) {
			st = mesh_error_set(err, lineno, MESH_EINVAL, "expected two finite numbers 'x y'");
			goto out;
		}
		if (*n >= max_seeds) {
			st = mesh_error_set(err, lineno, MESH_EINVAL, "too many seeds (at most %d)", max_seeds);
			goto out;
		}
		if ((size_t)*n == size) {
			size_t ns = size ? 2 * size : 1024;
			double *nv = (double *)std::realloc(v, 2 * ns * sizeof *v);
			if (nv == NULL) {
				st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
				goto out;
			}
			v = nv;
			size = ns;
		}
		v[2 * *n] = x;
		v[2 * *n + 1] = y;
		(*n)++;
	}
	if (std::ferror(f)) {
		st = mesh_error_set(err, 0, MESH_EIO, "read error: %s", std::strerror(errno));
		goto out;
	}
out:
	std::free(line);
	if (st != MESH_OK) {
		std::free(v);
		*n = 0;
		return st;
	}
	*xy = v;
	return MESH_OK;
}

extern "C" int voronoi_tissue(double lx, double ly, int n, const double *xy,
                              mesh **out, voronoi_info *info, mesh_error *err)
{
	*out = NULL;
	if (range_box(lx, ly, err) != MESH_OK)
		return MESH_EINVAL;
	return guarded(err, [&]() {
		Tessellation t;
		tessellate(lx, ly, n, xy, t, err);
		std::vector<double> r(t.rv.size());
		for (int v = 0; v < t.nv(); v++) {
			r[2 * v] = wrap(t.rv[2 * v], lx);
			r[2 * v + 1] = wrap(t.rv[2 * v + 1], ly);
		}
		mesh_error merr;
		int st = mesh_from_cells(lx, ly, t.nv(), r.data(), n, t.coff.data(), t.cv.data(),
		                         out, &merr);
		if (st == MESH_EINVAL)
			return mesh_error_set(err, 0, st, "these seeds give no valid periodic tissue: %s",
			                 merr.msg);
		if (st != MESH_OK)
			return mesh_error_set(err, 0, st, "%s", merr.msg);
		if (info) {
			info->nsplit = t.nsplit;
			info->npoints = t.npoints;
		}
		return (int)MESH_OK;
	});
}

extern "C" int voronoi_lloyd(double lx, double ly, int n, double *xy, int k,
                             mesh_error *err)
{
	if (range_box(lx, ly, err) != MESH_OK)
		return MESH_EINVAL;
	return guarded(err, [&]() {
		if (k < 0)
			FAIL(err, MESH_EINVAL, "negative number of Lloyd iterations");
		std::vector<double> c(2 * (size_t)(n > 0 ? n : 0));
		for (int it = 0; it < k; it++) {
			Tessellation t;
			tessellate(lx, ly, n, xy, t, err);
			for (int s = 0; s < n; s++) {
				/* relative to the seed, for accuracy far from the origin */
				double sx = t.s[2 * s], sy = t.s[2 * s + 1];
				double a = 0, cx = 0, cy = 0;
				int b = t.coff[s], e = t.coff[s + 1];
				for (int i = b; i < e; i++) {
					int j = i + 1 < e ? i + 1 : b;
					double x0 = t.corner_x(i) - sx, y0 = t.corner_y(i) - sy;
					double x1 = t.corner_x(j) - sx, y1 = t.corner_y(j) - sy;
					double w = x0 * y1 - x1 * y0;
					a += w;
					cx += (x0 + x1) * w;
					cy += (y0 + y1) * w;
				}
				if (!(a > 0))
					FAIL(err, MESH_EINVAL, "cell %d has no positive area", s);
				c[2 * s] = wrap(sx + cx / (3 * a), lx);
				c[2 * s + 1] = wrap(sy + cy / (3 * a), ly);
			}
			std::copy(c.begin(), c.end(), xy);
		}
		return (int)MESH_OK;
	});
}
