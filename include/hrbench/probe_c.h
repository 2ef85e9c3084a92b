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
 * no part records. (Alternatively, guard one probe with a lock of the kernel's.)
 *
 * Errors: every function that takes a probe returns 0 or a negative HRBENCH_PROBE_E*
 * code, and never writes out of bounds whatever it is given: a path one level past the
 * safety depth, a NULL argument, a probe used after hrbench_probe_finish. The first
 * error sticks to the probe (a part's passes to its probe at the merge), and
 * hrbench_probe_finish returns it: a kernel that checks only that call misses none. */
#ifndef HRBENCH_PROBE_C_H
#define HRBENCH_PROBE_C_H

#include <stdint.h>
#include <stdio.h>

/* The first line of every link dump of this probe: the format's name and version. */
#define HRBENCH_PROBE_DUMP_HEADER "hrbench-link-dump 2"
/* The deepest element a path names (hrbench's safety depth). */
#define HRBENCH_PROBE_SAFETY_DEPTH 48
/* The most children of an element (the quadtree); child indices are 0 to 3. */
#define HRBENCH_PROBE_MAX_CHILDREN 4
/* The longest element token, "4294967295/" and 48 digits, with its terminating NUL. */
#define HRBENCH_PROBE_TOKEN_SIZE (10 + 1 + HRBENCH_PROBE_SAFETY_DEPTH + 1)

/* The error codes (docs/probe-c.md#errors); 0 is success. */
#define HRBENCH_PROBE_EWRITE (-1)  /* a write to the dump failed */
#define HRBENCH_PROBE_EPATH (-2)   /* a path past the safety depth, or not made by child */
#define HRBENCH_PROBE_ENULL (-3)   /* a NULL probe, path or conventions string */
#define HRBENCH_PROBE_ECLOSED (-4) /* used after finish (a part after merge), or unopened */
#define HRBENCH_PROBE_ERANGE (-5)  /* a depth or a limit out of range */

/* An element as hrbench names it: the index of its root patch in scene order and its
 * child indices from that root, one digit a level ('0' the first child, up to '1' with
 * binary subdivision, '3' with the quadtree), NUL-terminated; depth = strlen(digits).
 * Written "3" for root 3 and "3/0110" below it. Depth -1 marks an invalid path, which
 * hrbench_probe_child returns past the safety depth. */
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

/* Whether a probe may record: set by open, cleared by finish (and by merge for a part). */
#define HRBENCH_PROBE_OPEN_ 0x68726270u /* "hrbp" */

typedef struct hrbench_probe {
    FILE *dump; /* NULL: count only */
    int failed; /* the first error, HRBENCH_PROBE_E*; 0 while none */
    hrbench_probe_counters counters;
    uint32_t open; /* HRBENCH_PROBE_OPEN_ while open */
} hrbench_probe;

/* Keeps the first error of _probe_ and returns _code_. */
static inline int hrbench_probe_fail_(hrbench_probe *probe, int code) {
    if (code && !probe->failed)
        probe->failed = code;
    return code;
}

/* 0 if _probe_ may record, else its error (NULL, closed). */
static inline int hrbench_probe_usable_(const hrbench_probe *probe) {
    if (!probe)
        return HRBENCH_PROBE_ENULL;
    return probe->open == HRBENCH_PROBE_OPEN_ ? 0 : HRBENCH_PROBE_ECLOSED;
}

/* 0 if _p_ is a path that root and child made, else its error. */
static inline int hrbench_probe_valid_(const hrbench_probe_path *p) {
    if (!p)
        return HRBENCH_PROBE_ENULL;
    if (p->depth < 0 || p->depth > HRBENCH_PROBE_SAFETY_DEPTH || p->digits[p->depth] != '\0')
        return HRBENCH_PROBE_EPATH;
    return 0;
}

/* The path of root patch _root_. */
static inline hrbench_probe_path hrbench_probe_root(uint32_t root) {
    hrbench_probe_path p;
    p.root = root;
    p.depth = 0;
    p.digits[0] = '\0';
    return p;
}

/* The child _c_ (0 to 3, in hrbench's subdivision order) of _p_. An invalid path (depth
 * -1, which every record refuses with HRBENCH_PROBE_EPATH) where _p_ is NULL or invalid,
 * _c_ is out of range or _p_ is at the safety depth already. */
static inline hrbench_probe_path hrbench_probe_child(const hrbench_probe_path *p, int c) {
    hrbench_probe_path q = hrbench_probe_root(p ? p->root : 0);
    if (hrbench_probe_valid_(p) || p->depth == HRBENCH_PROBE_SAFETY_DEPTH || c < 0 ||
        c >= HRBENCH_PROBE_MAX_CHILDREN) {
        q.depth = -1;
        return q;
    }
    q = *p;
    q.digits[q.depth++] = (char)('0' + c);
    q.digits[q.depth] = '\0';
    return q;
}

/* Writes the token of _p_ ("3", "3/0110") into _out_, HRBENCH_PROBE_TOKEN_SIZE bytes;
 * returns 0, or the error of an invalid path (then _out_ holds ""). */
static inline int hrbench_probe_format(const hrbench_probe_path *p, char *out) {
    int error = out ? hrbench_probe_valid_(p) : HRBENCH_PROBE_ENULL;
    if (!out)
        return error;
    if (error)
        out[0] = '\0';
    else if (p->depth)
        snprintf(out, HRBENCH_PROBE_TOKEN_SIZE, "%lu/%.*s", (unsigned long)p->root, p->depth,
                 p->digits);
    else
        snprintf(out, HRBENCH_PROBE_TOKEN_SIZE, "%lu", (unsigned long)p->root);
    return error;
}

/* 0 if _probe_ may record, else its error, kept by the probe (where not NULL). */
static inline int hrbench_probe_enter_(hrbench_probe *probe) {
    int error = hrbench_probe_usable_(probe);
    return error && probe ? hrbench_probe_fail_(probe, error) : error;
}

/* As hrbench_probe_enter_, and checks the paths _x_ and _y_ of a record where the probe
 * has a dump (a probe that counts reads no path). */
static inline int hrbench_probe_enter_pair_(hrbench_probe *probe, const hrbench_probe_path *x,
                                            const hrbench_probe_path *y) {
    int error = hrbench_probe_enter_(probe);
    if (error || !probe->dump)
        return error;
    error = hrbench_probe_valid_(x);
    return hrbench_probe_fail_(probe, error ? error : hrbench_probe_valid_(y));
}

/* Writes "WORD X Y TAIL" (WORD and TAIL may be empty) with one fputs (thread safety). */
static inline int hrbench_probe_record_(hrbench_probe *probe, const char *word,
                                        const hrbench_probe_path *x, const hrbench_probe_path *y,
                                        const char *tail, const hrbench_probe_path *z) {
    char a[HRBENCH_PROBE_TOKEN_SIZE], b[HRBENCH_PROBE_TOKEN_SIZE], c[HRBENCH_PROBE_TOKEN_SIZE];
    char line[3 * HRBENCH_PROBE_TOKEN_SIZE + 40];
    if (!probe->dump)
        return 0;
    hrbench_probe_format(x, a);
    hrbench_probe_format(y, b);
    c[0] = '\0';
    if (z)
        hrbench_probe_format(z, c);
    snprintf(line, sizeof line, "%s%s%s %s%s%s\n", word, *word ? " " : "", a, b, tail, c);
    if (fputs(line, probe->dump) == EOF)
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_EWRITE);
    return 0;
}

/* Starts a probe. With a stream (not NULL) it writes the header now, and the conventions
 * line where _conventions_ is not empty: the KEY=VALUE words where the kernel's rules
 * differ from hrbench's (docs/probe.md, Conventions). NULL _conventions_ is
 * HRBENCH_PROBE_ENULL: the probe is open, counts, and writes nothing. */
static inline int hrbench_probe_open(hrbench_probe *probe, FILE *dump, const char *conventions) {
    hrbench_probe_counters zero = {0, 0, 1, 0, 0, 0, 0};
    if (!probe)
        return HRBENCH_PROBE_ENULL;
    probe->dump = dump;
    probe->failed = 0;
    probe->counters = zero;
    probe->open = HRBENCH_PROBE_OPEN_;
    if (!conventions) {
        probe->dump = NULL;
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_ENULL);
    }
    if (dump && fprintf(dump, "%s\n", HRBENCH_PROBE_DUMP_HEADER) < 0)
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_EWRITE);
    if (dump && *conventions && fprintf(dump, "conventions %s\n", conventions) < 0)
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_EWRITE);
    return 0;
}

/* A part of _probe_ for one thread: the same stream, counters of its own (all 0). */
static inline int hrbench_probe_part(hrbench_probe *part, const hrbench_probe *probe) {
    int error = hrbench_probe_usable_(probe);
    if (!part)
        return HRBENCH_PROBE_ENULL;
    hrbench_probe_open(part, NULL, "");
    part->counters.passes = 0;
    if (error)
        return hrbench_probe_fail_(part, error);
    part->dump = probe->dump;
    return 0;
}

/* Adds the counters of _part_ to _probe_, after the part's thread has joined; the part
 * is closed, so that it is never counted twice. */
static inline int hrbench_probe_merge(hrbench_probe *probe, hrbench_probe *part) {
    hrbench_probe_counters *c;
    const hrbench_probe_counters *d;
    int error = hrbench_probe_enter_(probe);
    if (error)
        return error;
    if ((error = hrbench_probe_usable_(part)) != 0)
        return hrbench_probe_fail_(probe, error);
    c = &probe->counters;
    d = &part->counters;
    c->oracle_calls += d->oracle_calls;
    c->total_oracle_calls += d->total_oracle_calls;
    c->links += d->links;
    c->nodes += d->nodes;
    c->forced_links += d->forced_links;
    if (d->max_depth > c->max_depth)
        c->max_depth = d->max_depth;
    part->open = 0;
    return hrbench_probe_fail_(probe, part->failed);
}

/* Once per element when it is created: every root (depth 0), every child. */
static inline int hrbench_probe_element_created(hrbench_probe *probe, int depth) {
    int error = hrbench_probe_enter_(probe);
    if (error)
        return error;
    if (depth < 0 || depth > HRBENCH_PROBE_SAFETY_DEPTH)
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_ERANGE);
    ++probe->counters.nodes;
    if ((uint64_t)depth > probe->counters.max_depth)
        probe->counters.max_depth = (uint64_t)depth;
    return 0;
}

/* One oracle call, for a kernel that records no decisions (then call hrbench_probe_link
 * for each link); one that does calls the four functions below instead. */
static inline int hrbench_probe_oracle_call(hrbench_probe *probe) {
    int error = hrbench_probe_enter_(probe);
    if (error)
        return error;
    ++probe->counters.oracle_calls;
    ++probe->counters.total_oracle_calls;
    return 0;
}

/* A link of _i_ and _j_ (receiver first with links=directed), without a decision record;
 * _forced_ when a recursion limit made it. */
static inline int hrbench_probe_link(hrbench_probe *probe, const hrbench_probe_path *i,
                                     const hrbench_probe_path *j, int forced) {
    int error = hrbench_probe_enter_pair_(probe, i, j);
    if (error)
        return error;
    ++probe->counters.links;
    probe->counters.forced_links += forced != 0;
    return hrbench_probe_record_(probe, "", i, j, "", NULL);
}

/* An oracle call on (i, j) that accepts: the decision and the link. */
static inline int hrbench_probe_accept(hrbench_probe *probe, const hrbench_probe_path *i,
                                       const hrbench_probe_path *j) {
    int error = hrbench_probe_enter_pair_(probe, i, j);
    if (error)
        return error;
    hrbench_probe_oracle_call(probe);
    error = hrbench_probe_record_(probe, "decide", i, j, " accept", NULL);
    return hrbench_probe_link(probe, i, j, 0) ? probe->failed : error;
}

/* An oracle call on (i, j) that refuses, the kernel splitting _split_ (i or j). */
static inline int hrbench_probe_split(hrbench_probe *probe, const hrbench_probe_path *i,
                                      const hrbench_probe_path *j,
                                      const hrbench_probe_path *split) {
    int error = hrbench_probe_enter_pair_(probe, i, j);
    if (error)
        return error;
    if (probe->dump && (error = hrbench_probe_valid_(split)) != 0)
        return hrbench_probe_fail_(probe, error);
    hrbench_probe_oracle_call(probe);
    return hrbench_probe_record_(probe, "decide", i, j, " split ", split);
}

/* An oracle call on (i, j) that refuses, _limit_ forcing the link: decision and link. */
static inline int hrbench_probe_forced(hrbench_probe *probe, const hrbench_probe_path *i,
                                       const hrbench_probe_path *j, hrbench_probe_limit limit) {
    int error = hrbench_probe_enter_pair_(probe, i, j);
    if (error)
        return error;
    if (limit != HRBENCH_PROBE_MIN_AREA && limit != HRBENCH_PROBE_MAX_DEPTH)
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_ERANGE);
    hrbench_probe_oracle_call(probe);
    error = hrbench_probe_record_(
        probe, "decide", i, j,
        limit == HRBENCH_PROBE_MIN_AREA ? " forced min_area" : " forced max_depth", NULL);
    return hrbench_probe_link(probe, i, j, 1) ? probe->failed : error;
}

/* The pair (i, j) culled (cull=elements): no oracle call, no link. */
static inline int hrbench_probe_cull(hrbench_probe *probe, const hrbench_probe_path *i,
                                     const hrbench_probe_path *j) {
    int error = hrbench_probe_enter_pair_(probe, i, j);
    return error ? error : hrbench_probe_record_(probe, "decide", i, j, " cull", NULL);
}

/* Removes the live link of _i_ and _j_; _forced_ as it was made. */
static inline int hrbench_probe_unlink(hrbench_probe *probe, const hrbench_probe_path *i,
                                       const hrbench_probe_path *j, int forced) {
    int error = hrbench_probe_enter_pair_(probe, i, j);
    if (error)
        return error;
    /* No check against 0: a part unlinks links that other parts made, and its counters,
     * differences, wrap around and add up right at the merge. */
    --probe->counters.links;
    probe->counters.forced_links -= forced != 0;
    return hrbench_probe_record_(probe, "unlink", i, j, "", NULL);
}

/* Starts the next pass (2, 3, ...): oracle_calls counts that pass's calls from now. */
static inline int hrbench_probe_pass(hrbench_probe *probe) {
    int error = hrbench_probe_enter_(probe);
    if (error)
        return error;
    ++probe->counters.passes;
    probe->counters.oracle_calls = 0;
    if (probe->dump &&
        fprintf(probe->dump, "pass %llu\n", (unsigned long long)probe->counters.passes) < 0)
        return hrbench_probe_fail_(probe, HRBENCH_PROBE_EWRITE);
    return 0;
}

/* Ends the dump with the counters line and closes the probe; returns 0 when every call
 * succeeded, else the first error (HRBENCH_PROBE_EWRITE: a write failed). */
static inline int hrbench_probe_finish(hrbench_probe *probe) {
    const hrbench_probe_counters *c;
    int error = hrbench_probe_enter_(probe);
    if (error)
        return error;
    c = &probe->counters;
    if (probe->dump &&
        (fprintf(probe->dump,
                 "counters links=%llu oracle_calls=%llu total_oracle_calls=%llu passes=%llu "
                 "nodes=%llu forced_links=%llu max_depth=%llu\n",
                 (unsigned long long)c->links, (unsigned long long)c->oracle_calls,
                 (unsigned long long)c->total_oracle_calls, (unsigned long long)c->passes,
                 (unsigned long long)c->nodes, (unsigned long long)c->forced_links,
                 (unsigned long long)c->max_depth) < 0 ||
         fflush(probe->dump) != 0 || ferror(probe->dump)))
        hrbench_probe_fail_(probe, HRBENCH_PROBE_EWRITE);
    probe->open = 0;
    return probe->failed;
}

/* The counters so far (all 0 for NULL); also after finish. */
static inline hrbench_probe_counters hrbench_probe_counts(const hrbench_probe *probe) {
    hrbench_probe_counters zero = {0, 0, 0, 0, 0, 0, 0};
    return probe ? probe->counters : zero;
}

#endif /* HRBENCH_PROBE_C_H */
