/* A hierarchical radiosity kernel in C99 whose conventions are not hrbench's: it keeps
 * one link per direction (receiver <- source), splits a tie in size on the source,
 * culls element pairs whose centres do not face each other, and refines in two passes
 * (at 4 eps, then every link evaluated again at eps: a refused link is removed and its
 * pair refined). Its oracle is garmann's, max(A_i, A_j) <= eps * r. It includes only
 * <hrbench/probe_c.h>, which writes the link dump that `hrbench check-links` judges
 * on the conventions the dump declares (docs/probe-c.md):
 *
 *   c_kernel 0.25 parallel 64 1 plates.dump
 *   hrbench check-links parallel l=64 d=1 --eps 0.25 --links plates.dump
 *   c_kernel 0.25 scene.json scene.dump        (scene.json as `hrbench save` writes it)
 *
 * Without a dump file it only counts. It prints its counters, one "name value" a line.
 * Exit codes: 0 success, 2 usage or input error, 3 the safety depth was reached. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hrbench/probe_c.h>

#define SAFETY_DEPTH 48

typedef struct {
    double ax, ay, bx, by; /* the segment a -> b */
    uint32_t parent;       /* the element itself for a root */
    uint32_t first_child;  /* 0 until the element is split */
    uint32_t root;
    int depth;
} element;

typedef struct {
    uint32_t receiver, source;
} link_rec;

typedef struct {
    element *e;
    size_t n, cap;
    link_rec *links; /* the links of pass 1, which pass 2 evaluates again */
    size_t nlinks, links_cap;
    int pass;
    size_t unlinks;  /* links of pass 1 that pass 2 removed */
    double *nx, *ny; /* the front normal of each root, b - a turned by +90 degrees */
    hrbench_probe *probe;
} kernel;

static void die(int code, const char *message, const char *what) {
    fprintf(stderr, "c_kernel: %s%s\n", message, what ? what : "");
    exit(code);
}

static void *grow(void *p, size_t *cap, size_t size) {
    *cap = *cap ? 2 * *cap : 64;
    p = realloc(p, *cap * size);
    if (!p)
        die(3, "out of memory", NULL);
    return p;
}

static uint32_t add_element(kernel *k, double ax, double ay, double bx, double by, uint32_t parent,
                            uint32_t root, int depth) {
    element *e;
    if (k->n == k->cap)
        k->e = grow(k->e, &k->cap, sizeof *k->e);
    e = &k->e[k->n];
    e->ax = ax, e->ay = ay, e->bx = bx, e->by = by;
    e->parent = parent == UINT32_MAX ? (uint32_t)k->n : parent;
    e->first_child = 0;
    e->root = root;
    e->depth = depth;
    hrbench_probe_element_created(k->probe, depth);
    return (uint32_t)k->n++;
}

/* A^2 = dx*dx + dy*dy, in that order. */
static double size2(const element *e) {
    double dx = e->bx - e->ax, dy = e->by - e->ay;
    return dx * dx + dy * dy;
}

/* The element's name in the dump: its root and its child digits from the root. */
static hrbench_probe_path path_of(const kernel *k, uint32_t e) {
    hrbench_probe_path p = hrbench_probe_root(k->e[e].root);
    int d = k->e[e].depth;
    if (!k->probe->dump)
        return p; /* counting only: the probe reads no path */
    p.depth = d;
    p.digits[d] = '\0';
    for (; k->e[e].parent != e; e = k->e[e].parent)
        p.digits[--d] = (char)('0' + (e - k->e[k->e[e].parent].first_child));
    return p;
}

/* The first child of _e_, halving it at its midpoint the first time. */
static uint32_t children(kernel *k, uint32_t e) {
    if (k->e[e].first_child == 0) {
        element p = k->e[e];
        double mx = 0.5 * (p.ax + p.bx), my = 0.5 * (p.ay + p.by);
        uint32_t first = add_element(k, p.ax, p.ay, mx, my, e, p.root, p.depth + 1);
        add_element(k, mx, my, p.bx, p.by, e, p.root, p.depth + 1);
        k->e[e].first_child = first;
    }
    return k->e[e].first_child;
}

/* Whether the point (x, y) lies strictly in front of the line of root _r_. */
static int in_front(const kernel *k, uint32_t r, double x, double y) {
    return k->nx[r] * (x - k->e[r].ax) + k->ny[r] * (y - k->e[r].ay) > 0;
}

/* Whether no point of root _s_ lies strictly in front of the line of root _r_. */
static int behind(const kernel *k, uint32_t r, uint32_t s) {
    return !in_front(k, r, k->e[s].ax, k->e[s].ay) && !in_front(k, r, k->e[s].bx, k->e[s].by);
}

/* Whether the centre of _j_ lies strictly in front of the line of _i_'s root. */
static int faces(const kernel *k, uint32_t i, uint32_t j) {
    const element *a = &k->e[i], *b = &k->e[j];
    double cx = 0.5 * (b->ax + b->bx) - 0.5 * (a->ax + a->bx);
    double cy = 0.5 * (b->ay + b->by) - 0.5 * (a->ay + a->by);
    return k->nx[a->root] * cx + k->ny[a->root] * cy > 0;
}

/* garmann: max(A_i, A_j) <= eps * r, r the distance of the midpoints. */
static int acceptable(const kernel *k, uint32_t i, uint32_t j, double eps) {
    const element *a = &k->e[i], *b = &k->e[j];
    double s = size2(a) > size2(b) ? size2(a) : size2(b);
    double dx = 0.5 * (a->ax + a->bx) - 0.5 * (b->ax + b->bx);
    double dy = 0.5 * (a->ay + a->by) - 0.5 * (b->ay + b->by);
    return sqrt(s) <= eps * sqrt(dx * dx + dy * dy);
}

/* A link (the probe wrote it with its decision): pass 1 keeps it for pass 2. */
static void add_link(kernel *k, uint32_t receiver, uint32_t source) {
    if (k->pass == 2)
        return; /* final: nothing evaluates it again */
    if (k->nlinks == k->links_cap)
        k->links = grow(k->links, &k->links_cap, sizeof *k->links);
    k->links[k->nlinks].receiver = receiver;
    k->links[k->nlinks++].source = source;
}

static void project(kernel *k, uint32_t i, uint32_t j, double eps);

/* Whether a refused pair (i <- j) splits its source: the larger on A^2, ties the source. */
static int splits_source(const kernel *k, uint32_t i, uint32_t j) {
    return size2(&k->e[j]) >= size2(&k->e[i]);
}

/* Splits the element splits_source picks and refines the children's pairs. */
static void split(kernel *k, uint32_t i, uint32_t j, double eps) {
    int split_source = splits_source(k, i, j);
    uint32_t p = split_source ? j : i, c;
    if (k->e[p].depth == SAFETY_DEPTH)
        die(3, "the recursion reached the safety depth 48", NULL);
    for (c = children(k, p); c < k->e[p].first_child + 2; ++c)
        split_source ? project(k, i, c, eps) : project(k, c, j, eps);
}

/* The oracle's decision on the pair (receiver i <- source j) at _eps_, recorded. */
static int decide(kernel *k, uint32_t i, uint32_t j, double eps) {
    hrbench_probe_path r = path_of(k, i), s = path_of(k, j);
    int ok = acceptable(k, i, j, eps);
    if (ok)
        hrbench_probe_accept(k->probe, &r, &s);
    else
        hrbench_probe_split(k->probe, &r, &s, splits_source(k, i, j) ? &s : &r);
    return ok;
}

static void project(kernel *k, uint32_t i, uint32_t j, double eps) {
    if (!faces(k, i, j) || !faces(k, j, i)) { /* culled: no oracle call, no link */
        hrbench_probe_path r = path_of(k, i), s = path_of(k, j);
        hrbench_probe_cull(k->probe, &r, &s);
    } else if (decide(k, i, j, eps)) {
        add_link(k, i, j);
    } else {
        split(k, i, j, eps);
    }
}

/* Pass 2: each link of pass 1 is evaluated again at _eps_; a refused one is removed
 * and its pair refined. */
static void second_pass(kernel *k, double eps) {
    size_t t, n = k->nlinks;
    k->pass = 2;
    hrbench_probe_pass(k->probe);
    for (t = 0; t < n; ++t) {
        uint32_t i = k->links[t].receiver, j = k->links[t].source;
        if (!decide(k, i, j, eps)) {
            hrbench_probe_path r = path_of(k, i), s = path_of(k, j);
            hrbench_probe_unlink(k->probe, &r, &s, 0);
            ++k->unlinks;
            split(k, i, j, eps);
        }
    }
}

/* The two plates of hrbench's `parallel l=L d=D`: P (0,0)->(l,0), Q (l,d)->(0,d). */
static size_t parallel_scene(double l, double d, double *xy) {
    double v[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    v[2] = l, v[4] = l, v[5] = d, v[7] = d;
    memcpy(xy, v, sizeof v);
    return 2;
}

/* The root segments of a scene as `hrbench save` writes it (2D): each patch's "a" and
 * "b" points, in order. A reader of that output, not of every JSON text. */
static size_t read_scene(const char *name, double **xy) {
    FILE *f = fopen(name, "rb");
    char *text, *at;
    long size;
    size_t n = 0, cap = 0;
    if (!f || fseek(f, 0, SEEK_END) || (size = ftell(f)) < 0 || fseek(f, 0, SEEK_SET))
        die(2, "cannot read the scene file ", name);
    text = malloc((size_t)size + 1);
    if (!text || fread(text, 1, (size_t)size, f) != (size_t)size)
        die(2, "cannot read the scene file ", name);
    text[size] = '\0';
    fclose(f);
    if (!strstr(text, "\"dimension\": 2") || !(at = strstr(text, "\"patches\"")))
        die(2, "not a 2D scene as `hrbench save` writes it: ", name);
    *xy = NULL;
    while ((at = strstr(at, "\"a\""))) {
        int c;
        if (n + 4 > cap)
            *xy = grow(*xy, &cap, sizeof **xy);
        for (c = 0; c < 4; ++c) { /* a.x a.y, then b.x b.y after the key "b" */
            char *end;
            if (c == 2 && !(at = strstr(at, "\"b\"")))
                die(2, "a patch without its point b in ", name);
            at += strcspn(at, "-0123456789");
            (*xy)[n + c] = strtod(at, &end);
            if (end == at || !isfinite((*xy)[n + c]))
                die(2, "a patch point that is not a number in ", name);
            at = end;
        }
        n += 4;
    }
    free(text);
    if (n < 8)
        die(2, "a scene needs two patches or more: ", name);
    return n / 4;
}

static int positive(const char *text, double *value) {
    char *end;
    *value = strtod(text, &end);
    return *text && !*end && isfinite(*value) && *value > 0;
}

int main(int argc, char **argv) {
    kernel k;
    hrbench_probe probe;
    hrbench_probe_counters c;
    double eps, l, d, *xy = NULL, pair[8];
    size_t roots, r, s;
    int dumparg;
    FILE *dump = NULL;
    memset(&k, 0, sizeof k);
    if (argc >= 3 && !strcmp(argv[2], "parallel")) {
        if ((argc != 5 && argc != 6) || !positive(argv[3], &l) || !positive(argv[4], &d))
            die(2, "usage: c_kernel EPS (parallel L D | SCENE.json) [DUMP]", NULL);
        roots = parallel_scene(l, d, pair);
        xy = pair;
        dumparg = 5;
    } else if (argc == 3 || argc == 4) {
        roots = read_scene(argv[2], &xy);
        dumparg = 3;
    } else {
        die(2, "usage: c_kernel EPS (parallel L D | SCENE.json) [DUMP]", NULL);
        return 2;
    }
    if (!positive(argv[1], &eps))
        die(2, "EPS must be a number > 0, got ", argv[1]);
    if (argc > dumparg && !(dump = fopen(argv[dumparg], "w")))
        die(2, "cannot write ", argv[dumparg]);

    hrbench_probe_open(&probe, dump, "links=directed tie=source cull=elements oracle=garmann");
    k.probe = &probe;
    k.nx = malloc(roots * sizeof *k.nx);
    k.ny = malloc(roots * sizeof *k.ny);
    if (!k.nx || !k.ny)
        die(3, "out of memory", NULL);
    for (r = 0; r < roots; ++r) {
        const double *p = xy + 4 * r;
        if (p[0] == p[2] && p[1] == p[3])
            die(2, "a patch of length 0", NULL);
        add_element(&k, p[0], p[1], p[2], p[3], UINT32_MAX, (uint32_t)r, 0);
        k.nx[r] = -(p[3] - p[1]), k.ny[r] = p[2] - p[0];
    }
    /* Pass 1 at 4 eps, every ordered root pair (receiver r <- source s) but those where
     * one patch lies wholly behind or in the line of the other. */
    k.pass = 1;
    for (r = 0; r < roots; ++r)
        for (s = 0; s < roots; ++s)
            if (r != s && !behind(&k, (uint32_t)r, (uint32_t)s) &&
                !behind(&k, (uint32_t)s, (uint32_t)r))
                project(&k, (uint32_t)r, (uint32_t)s, 4 * eps);
    second_pass(&k, eps);
    if (hrbench_probe_finish(&probe) != 0 || (dump && fclose(dump) != 0))
        die(2, "cannot write ", argv[dumparg]);

    c = hrbench_probe_counts(&probe);
    printf("links %llu\noracle_calls %llu\ntotal_oracle_calls %llu\nnodes %llu\nmax_depth %llu\n"
           "unlinks %lu\n",
           (unsigned long long)c.links, (unsigned long long)c.oracle_calls,
           (unsigned long long)c.total_oracle_calls, (unsigned long long)c.nodes,
           (unsigned long long)c.max_depth, (unsigned long)k.unlinks);
    free(k.e), free(k.links), free(k.nx), free(k.ny);
    if (xy != pair)
        free(xy);
    return 0;
}
