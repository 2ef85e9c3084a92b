/* The C probe (include/hrbench/probe_c.h), compiled as C99: every record of a hand-written
 * dump, and the probe under threads: a refinement of two parallel plates (garmann,
 * hrbench's recursion) is first recorded as a list of probe calls; replaying it on one
 * thread and spread over several threads, each with a part of its own
 * (hrbench_probe_part, hrbench_probe_merge) writing to the same stream, must give the
 * same dump as a set of lines and the same counters. Exit code 0 when every check passes. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hrbench/probe_c.h>

static int failures = 0;
#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);               \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

/* One probe call of the recorded refinement. */
typedef struct {
    enum { CREATED, ACCEPT, SPLIT, UNLINK } kind;
    hrbench_probe_path i, j;
    int value; /* the depth of CREATED; for SPLIT, 0: i is split, 1: j */
} event;

typedef struct {
    event *e;
    size_t n, cap;
} events;

static void push(events *list, event e) {
    if (list->n == list->cap) {
        list->cap = list->cap ? 2 * list->cap : 1024;
        list->e = realloc(list->e, list->cap * sizeof *list->e);
        if (!list->e)
            abort();
    }
    list->e[list->n++] = e;
}

/* An element of a plate: the interval [t0, t1] of its root, its path, whether split. */
typedef struct {
    double y, t0, t1;
    hrbench_probe_path path;
} segment;

static void created(events *list, const hrbench_probe_path *p) {
    event e;
    memset(&e, 0, sizeof e);
    e.kind = CREATED;
    e.i = *p;
    e.value = p->depth;
    push(list, e);
}

/* hrbench's ProjectKernel on plates y=0 and y=d with garmann; an element is "created"
 * by the first split that needs it, tracked by a bit per path of the complete tree. */
static void project(events *list, unsigned char *split_done, segment i, segment j, double eps) {
    double ai = i.t1 - i.t0, aj = j.t1 - j.t0, dx = 0.5 * (i.t0 + i.t1) - 0.5 * (j.t0 + j.t1);
    double dy = i.y - j.y;
    event e;
    segment *p, c[2];
    int k;
    unsigned long index;
    memset(&e, 0, sizeof e);
    e.i = i.path, e.j = j.path;
    if ((ai > aj ? ai : aj) <= eps * sqrt(dx * dx + dy * dy)) {
        e.kind = ACCEPT;
        push(list, e);
        return;
    }
    e.kind = SPLIT;
    e.value = ai * ai >= aj * aj ? 0 : 1;
    push(list, e);
    p = e.value == 0 ? &i : &j;
    index = (1ul << p->path.depth) + strtoul(p->path.digits[0] ? p->path.digits : "0", NULL, 2);
    index = 2 * index + p->path.root; /* the two plates' trees interleaved */
    for (k = 0; k < 2; ++k) {
        c[k] = *p;
        c[k].path = hrbench_probe_child(&p->path, k);
        (k ? &c[k].t0 : &c[k].t1)[0] = 0.5 * (p->t0 + p->t1);
        if (!split_done[index])
            created(list, &c[k].path);
    }
    split_done[index] = 1;
    for (k = 0; k < 2; ++k)
        if (p == &i)
            project(list, split_done, c[k], j, eps);
        else
            project(list, split_done, i, c[k], eps);
}

/* Replays the events k with k % stride == offset through _probe_. */
static void replay(hrbench_probe *probe, const events *list, size_t offset, size_t stride) {
    size_t k;
    for (k = offset; k < list->n; k += stride) {
        const event *e = &list->e[k];
        switch (e->kind) {
        case CREATED:
            hrbench_probe_element_created(probe, e->value);
            break;
        case ACCEPT:
            hrbench_probe_accept(probe, &e->i, &e->j);
            break;
        case SPLIT:
            hrbench_probe_split(probe, &e->i, &e->j, e->value ? &e->j : &e->i);
            break;
        case UNLINK:
            hrbench_probe_unlink(probe, &e->i, &e->j, 0);
            break;
        }
    }
}

typedef struct {
    hrbench_probe part;
    const events *list;
    size_t offset, stride;
} job;

static void *run_job(void *arg) {
    job *w = arg;
    replay(&w->part, w->list, w->offset, w->stride);
    return NULL;
}

static int compare_lines(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void free_lines(char **lines, size_t n) {
    size_t k;
    for (k = 0; k < n; ++k)
        free(lines[k]);
    free(lines);
}

/* The dump written to _f_ as its lines, sorted; *n their number. */
static char **sorted_lines(FILE *f, size_t *n) {
    char **lines = NULL, buf[256];
    size_t cap = 0;
    *n = 0;
    rewind(f);
    while (fgets(buf, sizeof buf, f)) {
        if (*n == cap) {
            cap = cap ? 2 * cap : 1024;
            lines = realloc(lines, cap * sizeof *lines);
            if (!lines)
                abort();
        }
        lines[*n] = malloc(strlen(buf) + 1);
        strcpy(lines[(*n)++], buf);
    }
    qsort(lines, *n, sizeof *lines, compare_lines);
    return lines;
}

/* Two passes, each replayed by _threads_ threads (1: by the probe itself). */
static hrbench_probe_counters record(FILE *f, const events passes[2], int threads) {
    hrbench_probe probe;
    int pass, t;
    hrbench_probe_open(&probe, f, "links=directed");
    hrbench_probe_element_created(&probe, 0);
    hrbench_probe_element_created(&probe, 0);
    for (pass = 0; pass < 2; ++pass) {
        job jobs[8];
        pthread_t ids[8];
        if (pass)
            hrbench_probe_pass(&probe);
        if (threads == 1) {
            replay(&probe, &passes[pass], 0, 1);
            continue;
        }
        for (t = 0; t < threads; ++t) {
            hrbench_probe_part(&jobs[t].part, &probe);
            jobs[t].list = &passes[pass], jobs[t].offset = (size_t)t,
            jobs[t].stride = (size_t)threads;
            CHECK(pthread_create(&ids[t], NULL, run_job, &jobs[t]) == 0);
        }
        for (t = 0; t < threads; ++t) {
            CHECK(pthread_join(ids[t], NULL) == 0);
            hrbench_probe_merge(&probe, &jobs[t].part);
        }
    }
    CHECK(hrbench_probe_finish(&probe) == 0);
    return hrbench_probe_counts(&probe);
}

/* The records of a small dump, written by hand: every kind of record and counter. */
static void hand_written(void) {
    static const char expected[] =
        "hrbench-link-dump 2\n"
        "conventions links=directed tie=source\n"
        "decide 0 1 accept\n0 1\n"
        "pass 2\n"
        "decide 0 1 split 1\n"
        "decide 0 1/0 cull\n"
        "decide 0 1/1 forced max_depth\n0 1/1\n"
        "unlink 0 1\n"
        "counters links=1 oracle_calls=2 total_oracle_calls=3 passes=2 nodes=4 "
        "forced_links=1 max_depth=1\n";
    hrbench_probe_path p = hrbench_probe_root(0), q = hrbench_probe_root(1), q0, q1, deep;
    hrbench_probe probes[2];
    hrbench_probe_counters c[2];
    char text[1024], token[HRBENCH_PROBE_TOKEN_SIZE];
    size_t n;
    int k;
    FILE *f = tmpfile();
    CHECK(f != NULL);
    q0 = hrbench_probe_child(&q, 0), q1 = hrbench_probe_child(&q, 1);
    for (k = 0; k < 2; ++k) { /* with a dump, and counting only */
        hrbench_probe *probe = &probes[k];
        hrbench_probe_open(probe, k ? NULL : f, "links=directed tie=source");
        hrbench_probe_element_created(probe, 0);
        hrbench_probe_element_created(probe, 0);
        hrbench_probe_accept(probe, &p, &q);
        hrbench_probe_pass(probe);
        hrbench_probe_split(probe, &p, &q, &q);
        hrbench_probe_element_created(probe, 1);
        hrbench_probe_element_created(probe, 1);
        hrbench_probe_cull(probe, &p, &q0);
        hrbench_probe_forced(probe, &p, &q1, HRBENCH_PROBE_MAX_DEPTH);
        hrbench_probe_unlink(probe, &p, &q, 0);
        CHECK(hrbench_probe_finish(probe) == 0);
        c[k] = hrbench_probe_counts(probe);
    }
    rewind(f);
    n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    CHECK(strcmp(text, expected) == 0);
    CHECK(memcmp(&c[0], &c[1], sizeof c[0]) == 0);
    CHECK(c[0].links == 1 && c[0].forced_links == 1 && c[0].total_oracle_calls == 3);
    fclose(f);

    /* The longest token: root 2^32 - 1, 48 digits. */
    deep = hrbench_probe_root(4294967295u);
    for (k = 0; k < HRBENCH_PROBE_SAFETY_DEPTH; ++k)
        deep = hrbench_probe_child(&deep, k % 2);
    hrbench_probe_format(&deep, token);
    CHECK(strlen(token) == HRBENCH_PROBE_TOKEN_SIZE - 1);
    CHECK(strncmp(token, "4294967295/0101", 15) == 0);
}

/* The bytes written to _f_ so far, into _text_ (at most _size_ - 1). */
static size_t contents(FILE *f, char *text, size_t size) {
    size_t n;
    fflush(f);
    rewind(f);
    n = fread(text, 1, size - 1, f);
    text[n] = '\0';
    return n;
}

/* What a kernel may get wrong is a documented error, never a write out of bounds (the
 * sanitizer build runs this): a path one level past the safety depth, NULL arguments, a
 * probe used after finish, a part merged twice; the first error sticks and finish
 * returns it. */
static void defends_its_invariants(void) {
    hrbench_probe probe, part;
    hrbench_probe_path p = hrbench_probe_root(0), q = hrbench_probe_root(1), deep, past, bad;
    char text[4096], token[HRBENCH_PROBE_TOKEN_SIZE];
    size_t before;
    int k;
    FILE *f = tmpfile();
    CHECK(f != NULL);

    /* A child past the safety depth, or of a child index out of range, is invalid. */
    deep = p;
    for (k = 0; k < HRBENCH_PROBE_SAFETY_DEPTH; ++k)
        deep = hrbench_probe_child(&deep, 1);
    CHECK(deep.depth == HRBENCH_PROBE_SAFETY_DEPTH);
    past = hrbench_probe_child(&deep, 0);
    CHECK(past.depth == -1);
    CHECK(hrbench_probe_child(&past, 0).depth == -1);
    CHECK(hrbench_probe_child(&p, 4).depth == -1 && hrbench_probe_child(&p, -1).depth == -1);
    CHECK(hrbench_probe_child(NULL, 0).depth == -1);
    CHECK(hrbench_probe_format(&past, token) == HRBENCH_PROBE_EPATH && token[0] == '\0');
    bad = p, bad.depth = 1000; /* made by hand, not by root and child */
    CHECK(hrbench_probe_format(&bad, token) == HRBENCH_PROBE_EPATH);
    CHECK(hrbench_probe_format(NULL, token) == HRBENCH_PROBE_ENULL);
    CHECK(hrbench_probe_format(&p, NULL) == HRBENCH_PROBE_ENULL);

    /* A record of an invalid path writes nothing; the error sticks to finish. */
    CHECK(hrbench_probe_open(&probe, f, "") == 0);
    before = contents(f, text, sizeof text);
    CHECK(hrbench_probe_accept(&probe, &past, &q) == HRBENCH_PROBE_EPATH);
    CHECK(hrbench_probe_split(&probe, &p, &q, &past) == HRBENCH_PROBE_EPATH);
    CHECK(hrbench_probe_accept(&probe, &p, NULL) == HRBENCH_PROBE_ENULL);
    CHECK(hrbench_probe_split(&probe, &p, &q, NULL) == HRBENCH_PROBE_ENULL);
    CHECK(contents(f, text, sizeof text) == before);
    CHECK(hrbench_probe_element_created(&probe, HRBENCH_PROBE_SAFETY_DEPTH + 1) ==
          HRBENCH_PROBE_ERANGE);
    CHECK(hrbench_probe_forced(&probe, &p, &q, (hrbench_probe_limit)7) == HRBENCH_PROBE_ERANGE);
    CHECK(hrbench_probe_counts(&probe).links == 0 && hrbench_probe_counts(&probe).nodes == 0);
    CHECK(hrbench_probe_accept(&probe, &p, &q) == 0);           /* a valid record still writes */
    CHECK(hrbench_probe_finish(&probe) == HRBENCH_PROBE_EPATH); /* the first error */

    /* Used after finish: refused, nothing written, no second counters line. */
    before = contents(f, text, sizeof text);
    CHECK(hrbench_probe_accept(&probe, &p, &q) == HRBENCH_PROBE_ECLOSED);
    CHECK(hrbench_probe_pass(&probe) == HRBENCH_PROBE_ECLOSED);
    CHECK(hrbench_probe_element_created(&probe, 0) == HRBENCH_PROBE_ECLOSED);
    CHECK(hrbench_probe_finish(&probe) == HRBENCH_PROBE_ECLOSED);
    CHECK(contents(f, text, sizeof text) == before);
    CHECK(hrbench_probe_counts(&probe).links == 1); /* the counters stay readable */

    /* NULL arguments. */
    CHECK(hrbench_probe_open(NULL, f, "") == HRBENCH_PROBE_ENULL);
    CHECK(hrbench_probe_finish(NULL) == HRBENCH_PROBE_ENULL);
    CHECK(hrbench_probe_accept(NULL, &p, &q) == HRBENCH_PROBE_ENULL);
    CHECK(hrbench_probe_counts(NULL).links == 0);
    CHECK(hrbench_probe_open(&probe, f, NULL) == HRBENCH_PROBE_ENULL); /* writes nothing */
    CHECK(contents(f, text, sizeof text) == before);
    CHECK(hrbench_probe_element_created(&probe, 0) == 0); /* it counts */
    CHECK(hrbench_probe_finish(&probe) == HRBENCH_PROBE_ENULL);
    CHECK(contents(f, text, sizeof text) == before);

    /* A part merged twice counts once; a part of a closed probe is refused. */
    CHECK(hrbench_probe_open(&probe, NULL, "") == 0);
    CHECK(hrbench_probe_part(&part, &probe) == 0);
    CHECK(hrbench_probe_element_created(&part, 3) == 0);
    CHECK(hrbench_probe_merge(&probe, &part) == 0);
    CHECK(hrbench_probe_merge(&probe, &part) == HRBENCH_PROBE_ECLOSED);
    CHECK(hrbench_probe_counts(&probe).nodes == 1 && hrbench_probe_counts(&probe).max_depth == 3);
    CHECK(hrbench_probe_finish(&probe) == HRBENCH_PROBE_ECLOSED);
    CHECK(hrbench_probe_part(&part, &probe) == HRBENCH_PROBE_ECLOSED);
    CHECK(hrbench_probe_part(NULL, &probe) == HRBENCH_PROBE_ENULL);

    /* A probe that only counts reads no path: any will do. */
    CHECK(hrbench_probe_open(&probe, NULL, "") == 0);
    CHECK(hrbench_probe_accept(&probe, &past, NULL) == 0);
    CHECK(hrbench_probe_finish(&probe) == 0 && hrbench_probe_counts(&probe).links == 1);
    fclose(f);
}

int main(void) {
    static unsigned char split_done[1u << 16];
    events passes[2];
    segment p, q;
    FILE *one, *many;
    size_t n1, nm, k;
    char **l1, **lm;
    hrbench_probe_counters c1, cm;
    int threads;

    hand_written();
    defends_its_invariants();
    /* Pass 1 refines plates l=64 d=1 at eps 0.2; pass 2 removes a link of pass 1 and
     * refines the plates again at eps 0.1 (not a consistent dump: what matters here is
     * every kind of call, many of them, from every thread). */
    memset(passes, 0, sizeof passes);
    memset(&p, 0, sizeof p);
    p.t1 = 64, p.path = hrbench_probe_root(0);
    q = p, q.y = 1, q.path = hrbench_probe_root(1);
    project(&passes[0], split_done, p, q, 0.2);
    {
        event e;
        size_t first = 0;
        while (passes[0].e[first].kind != ACCEPT)
            ++first;
        memset(&e, 0, sizeof e);
        e.kind = UNLINK, e.i = passes[0].e[first].i, e.j = passes[0].e[first].j;
        push(&passes[1], e);
        memset(split_done, 0, sizeof split_done);
        project(&passes[1], split_done, p, q, 0.1);
    }
    CHECK(passes[0].n > 10000);

    one = tmpfile();
    CHECK(one != NULL);
    c1 = record(one, passes, 1);
    l1 = sorted_lines(one, &n1);
    for (threads = 2; threads <= 8; threads *= 2) {
        many = tmpfile();
        CHECK(many != NULL);
        cm = record(many, passes, threads);
        lm = sorted_lines(many, &nm);
        CHECK(memcmp(&c1, &cm, sizeof c1) == 0);
        CHECK(n1 == nm);
        for (k = 0; k < n1 && k < nm; ++k)
            if (strcmp(l1[k], lm[k]) != 0) {
                fprintf(stderr, "%d threads: line %s differs from %s", threads, lm[k], l1[k]);
                ++failures;
                break;
            }
        free_lines(lm, nm);
        fclose(many);
    }
    free_lines(l1, n1);
    free(passes[0].e);
    free(passes[1].e);
    fclose(one);
    printf("probe_c_test: %lu calls, %lu links, %lu lines, same with 2, 4, 8 threads: %s\n",
           (unsigned long)c1.total_oracle_calls, (unsigned long)c1.links, (unsigned long)n1,
           failures ? "FAILED" : "ok");
    return failures ? 1 : 0;
}
