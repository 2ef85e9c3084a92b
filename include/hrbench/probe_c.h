/* The probe for a kernel written in C: counters as hrbench counts them and the link dump,
 * version 2 (docs/probe.md), that `hrbench check-links` judges on the conventions the
 * kernel declares. Header-only C99 (static inline functions, the C standard library
 * only): a C program includes it and links without a C++ runtime. docs/probe-c.md.
 *
 *   hrbench_probe probe;
 *   hrbench_probe_open(&probe, dump, "links=directed tie=source");  (dump NULL: count only)
 *   ... for each root patch r:     hrbench_probe_element_created(&probe, 0);
 *   ... for each child created:    hrbench_probe_element_created(&probe, depth);
 *   ... at each oracle call on (i, j), what the kernel decided:
 *         hrbench_probe_accept(&probe, &i, &j);              (writes the link too)
 *         hrbench_probe_split(&probe, &i, &j, &i);            (or &j: the element split)
 *         hrbench_probe_forced(&probe, &i, &j, HRBENCH_PROBE_MIN_AREA);  (links it)
 *   ... a pair culled without an oracle call:  hrbench_probe_cull(&probe, &i, &j);
 *   ... a second pass:             hrbench_probe_pass(&probe);
 *   ... a link removed:            hrbench_probe_unlink(&probe, &i, &j, forced);
 *   hrbench_probe_finish(&probe);                      (the counters line; 0 or -1)
 *
 * A probe without a dump reads no path: a kernel that only counts may pass any.
 *
 * Thread safety: a probe is never used by two threads at once. A kernel that refines on
 * several threads gives each thread a part of the probe, hrbench_probe_part(&part,
 * &probe), which writes its records to the probe's stream with counters of its own;
 * after the threads have joined, hrbench_probe_merge(&probe, &part) adds each part's
 * counters to the probe. Every record is formatted into a local buffer and written with
 * one fputs call, and POSIX stdio locks the stream for the length of each call, so the
 * lines of several parts never mix within a line; their order between parts is that of
 * the threads. hrbench_probe_pass and hrbench_probe_finish are called on the probe while
 * no part records. (Alternatively, guard one probe with a lock of the kernel's.) */
#ifndef HRBENCH_PROBE_C_H
#define HRBENCH_PROBE_C_H

#include <stdint.h>
#include <stdio.h>

/* The first line of every link dump of this probe: the format's name and version. */
#define HRBENCH_PROBE_DUMP_HEADER "hrbench-link-dump 2"
/* The deepest element a path names (hrbench's safety depth). */
#define HRBENCH_PROBE_SAFETY_DEPTH 48
/* The longest element token, "4294967295/" and 48 digits, with its terminating NUL. */
#define HRBENCH_PROBE_TOKEN_SIZE (10 + 1 + HRBENCH_PROBE_SAFETY_DEPTH + 1)

/* An element as hrbench names it: the index of its root patch in scene order and its
 * child indices from that root, one digit a level ('0' the first child, up to '1' with
 * binary subdivision, '3' with the quadtree), NUL-terminated; depth = strlen(digits).
 * Written "3" for root 3 and "3/0110" below it. */
typedef struct hrbench_probe_path {
    uint32_t root;
    int depth;
    char digits[HRBENCH_PROBE_SAFETY_DEPTH + 1];
} hrbench_probe_path;

/* What a kernel counts, named as on the counters line (docs/probe.md). */
typedef struct hrbench_probe_counters {
    uint64_t oracle_calls;       /* oracle calls of the current (last) pass */
    uint64_t total_oracle_calls; /* oracle calls of all passes */
    uint64_t passes;             /* 1 until hrbench_probe_pass */
    uint64_t links;              /* live links: made less removed, forced ones included */
    uint64_t nodes;              /* elements created, roots included */
    uint64_t forced_links;       /* live links made by a recursion limit */
    uint64_t max_depth;          /* depth of the deepest element; roots have depth 0 */
} hrbench_probe_counters;

/* The recursion limit that forced a link. */
typedef enum hrbench_probe_limit {
    HRBENCH_PROBE_MIN_AREA, /* --min-area */
    HRBENCH_PROBE_MAX_DEPTH /* --max-depth */
} hrbench_probe_limit;

typedef struct hrbench_probe {
    FILE *dump; /* NULL: count only */
    int failed; /* a write failed */
    hrbench_probe_counters counters;
} hrbench_probe;

/* The path of root patch _root_. */
static inline hrbench_probe_path hrbench_probe_root(uint32_t root) {
    hrbench_probe_path p;
    p.root = root;
    p.depth = 0;
    p.digits[0] = '\0';
    return p;
}

/* The child _c_ (0-based, in hrbench's subdivision order) of _p_, which must be shallower
 * than HRBENCH_PROBE_SAFETY_DEPTH. */
static inline hrbench_probe_path hrbench_probe_child(const hrbench_probe_path *p, int c) {
    hrbench_probe_path q = *p;
    q.digits[q.depth++] = (char)('0' + c);
    q.digits[q.depth] = '\0';
    return q;
}

/* Writes the token of _p_ ("3", "3/0110") into _out_, HRBENCH_PROBE_TOKEN_SIZE bytes. */
static inline void hrbench_probe_format(const hrbench_probe_path *p, char *out) {
    if (p->depth)
        sprintf(out, "%lu/%s", (unsigned long)p->root, p->digits);
    else
        sprintf(out, "%lu", (unsigned long)p->root);
}

/* Writes "WORD X Y TAIL" (WORD and TAIL may be empty) with one fputs (thread safety). */
static inline void hrbench_probe_record_(hrbench_probe *probe, const char *word,
                                         const hrbench_probe_path *x, const hrbench_probe_path *y,
                                         const char *tail, const hrbench_probe_path *z) {
    char a[HRBENCH_PROBE_TOKEN_SIZE], b[HRBENCH_PROBE_TOKEN_SIZE], c[HRBENCH_PROBE_TOKEN_SIZE];
    char line[3 * HRBENCH_PROBE_TOKEN_SIZE + 40];
    if (!probe->dump)
        return;
    hrbench_probe_format(x, a);
    hrbench_probe_format(y, b);
    c[0] = '\0';
    if (z)
        hrbench_probe_format(z, c);
    sprintf(line, "%s%s%s %s%s%s\n", word, *word ? " " : "", a, b, tail, c);
    if (fputs(line, probe->dump) == EOF)
        probe->failed = 1;
}

/* Starts a probe. With a stream (not NULL) it writes the header now, and the conventions
 * line where _conventions_ is not empty: the KEY=VALUE words where the kernel's rules
 * differ from hrbench's (docs/probe.md, Conventions). */
static inline void hrbench_probe_open(hrbench_probe *probe, FILE *dump, const char *conventions) {
    hrbench_probe_counters zero = {0, 0, 1, 0, 0, 0, 0};
    probe->dump = dump;
    probe->failed = 0;
    probe->counters = zero;
    if (dump && fprintf(dump, "%s\n", HRBENCH_PROBE_DUMP_HEADER) < 0)
        probe->failed = 1;
    if (dump && *conventions && fprintf(dump, "conventions %s\n", conventions) < 0)
        probe->failed = 1;
}

/* A part of _probe_ for one thread: the same stream, counters of its own (all 0). */
static inline void hrbench_probe_part(hrbench_probe *part, const hrbench_probe *probe) {
    hrbench_probe_open(part, NULL, "");
    part->counters.passes = 0;
    part->dump = probe->dump;
}

/* Adds the counters of _part_ to _probe_, after the part's thread has joined. */
static inline void hrbench_probe_merge(hrbench_probe *probe, const hrbench_probe *part) {
    hrbench_probe_counters *c = &probe->counters;
    const hrbench_probe_counters *d = &part->counters;
    c->oracle_calls += d->oracle_calls;
    c->total_oracle_calls += d->total_oracle_calls;
    c->links += d->links;
    c->nodes += d->nodes;
    c->forced_links += d->forced_links;
    if (d->max_depth > c->max_depth)
        c->max_depth = d->max_depth;
    probe->failed |= part->failed;
}

/* Once per element when it is created: every root (depth 0), every child. */
static inline void hrbench_probe_element_created(hrbench_probe *probe, int depth) {
    ++probe->counters.nodes;
    if ((uint64_t)depth > probe->counters.max_depth)
        probe->counters.max_depth = (uint64_t)depth;
}

/* One oracle call, for a kernel that records no decisions (then call hrbench_probe_link
 * for each link); one that does calls the four functions below instead. */
static inline void hrbench_probe_oracle_call(hrbench_probe *probe) {
    ++probe->counters.oracle_calls;
    ++probe->counters.total_oracle_calls;
}

/* A link of _i_ and _j_ (receiver first with links=directed), without a decision record;
 * _forced_ when a recursion limit made it. */
static inline void hrbench_probe_link(hrbench_probe *probe, const hrbench_probe_path *i,
                                      const hrbench_probe_path *j, int forced) {
    ++probe->counters.links;
    probe->counters.forced_links += forced != 0;
    hrbench_probe_record_(probe, "", i, j, "", NULL);
}

/* An oracle call on (i, j) that accepts: the decision and the link. */
static inline void hrbench_probe_accept(hrbench_probe *probe, const hrbench_probe_path *i,
                                        const hrbench_probe_path *j) {
    hrbench_probe_oracle_call(probe);
    hrbench_probe_record_(probe, "decide", i, j, " accept", NULL);
    hrbench_probe_link(probe, i, j, 0);
}

/* An oracle call on (i, j) that refuses, the kernel splitting _split_ (i or j). */
static inline void hrbench_probe_split(hrbench_probe *probe, const hrbench_probe_path *i,
                                       const hrbench_probe_path *j,
                                       const hrbench_probe_path *split) {
    hrbench_probe_oracle_call(probe);
    hrbench_probe_record_(probe, "decide", i, j, " split ", split);
}

/* An oracle call on (i, j) that refuses, _limit_ forcing the link: decision and link. */
static inline void hrbench_probe_forced(hrbench_probe *probe, const hrbench_probe_path *i,
                                        const hrbench_probe_path *j, hrbench_probe_limit limit) {
    hrbench_probe_oracle_call(probe);
    hrbench_probe_record_(
        probe, "decide", i, j,
        limit == HRBENCH_PROBE_MIN_AREA ? " forced min_area" : " forced max_depth", NULL);
    hrbench_probe_link(probe, i, j, 1);
}

/* The pair (i, j) culled (cull=elements): no oracle call, no link. */
static inline void hrbench_probe_cull(hrbench_probe *probe, const hrbench_probe_path *i,
                                      const hrbench_probe_path *j) {
    hrbench_probe_record_(probe, "decide", i, j, " cull", NULL);
}

/* Removes the live link of _i_ and _j_; _forced_ as it was made. */
static inline void hrbench_probe_unlink(hrbench_probe *probe, const hrbench_probe_path *i,
                                        const hrbench_probe_path *j, int forced) {
    --probe->counters.links;
    probe->counters.forced_links -= forced != 0;
    hrbench_probe_record_(probe, "unlink", i, j, "", NULL);
}

/* Starts the next pass (2, 3, ...): oracle_calls counts that pass's calls from now. */
static inline void hrbench_probe_pass(hrbench_probe *probe) {
    ++probe->counters.passes;
    probe->counters.oracle_calls = 0;
    if (probe->dump &&
        fprintf(probe->dump, "pass %llu\n", (unsigned long long)probe->counters.passes) < 0)
        probe->failed = 1;
}

/* Ends the dump with the counters line; 0 when every write succeeded, -1 otherwise. */
static inline int hrbench_probe_finish(hrbench_probe *probe) {
    const hrbench_probe_counters *c = &probe->counters;
    if (probe->dump &&
        (fprintf(probe->dump,
                 "counters links=%llu oracle_calls=%llu total_oracle_calls=%llu passes=%llu "
                 "nodes=%llu forced_links=%llu max_depth=%llu\n",
                 (unsigned long long)c->links, (unsigned long long)c->oracle_calls,
                 (unsigned long long)c->total_oracle_calls, (unsigned long long)c->passes,
                 (unsigned long long)c->nodes, (unsigned long long)c->forced_links,
                 (unsigned long long)c->max_depth) < 0 ||
         fflush(probe->dump) != 0 || ferror(probe->dump)))
        probe->failed = 1;
    return probe->failed ? -1 : 0;
}

/* The counters so far. */
static inline hrbench_probe_counters hrbench_probe_counts(const hrbench_probe *probe) {
    return probe->counters;
}

#endif /* HRBENCH_PROBE_C_H */
