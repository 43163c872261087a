/* Library error details as command-line messages (see hostio.h). */
#include "hostio.h"

#include "actag/common.h"

#include <stdio.h>
#include <string.h>

static const hostio_optname *lookup(const hostio_optname *map, int nmap, const char *field)
{
    int i;
    if (field == NULL)
        return NULL;
    for (i = 0; i < nmap; i++)
        if (map[i].field != NULL && strcmp(map[i].field, field) == 0)
            return &map[i];
    return NULL;
}

static int word_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '_';
}

/* A name (letters, digits, '_' and inner dots) starts at s / ends before e. */
static int starts_name(const char *rule, const char *s)
{
    return s == rule || !(word_char(s[-1]) || s[-1] == '.');
}
static int ends_name(const char *e) { return !(word_char(e[0]) || (e[0] == '.' && word_char(e[1]))); }

/* rule with every whole field name of the map replaced by its option. */
static void translate(const char *rule, const hostio_optname *map, int nmap, char *out,
                      size_t n)
{
    size_t o = 0;
    const char *s = rule;
    while (*s && o + 1 < n) {
        int i, done = 0;
        if (starts_name(rule, s))
            for (i = 0; i < nmap && !done; i++) {
                size_t len = map[i].field ? strlen(map[i].field) : 0;
                if (len && strncmp(s, map[i].field, len) == 0 && ends_name(s + len)) {
                    int w = snprintf(out + o, n - o, "%s", map[i].option);
                    o = w < 0 || (size_t)w >= n - o ? n - 1 : o + (size_t)w;
                    s += len;
                    done = 1;
                }
            }
        if (!done)
            out[o++] = *s++;
    }
    out[o] = '\0';
}

/* A value as the user would write it: whole numbers in full (%g printed
 * -2147483648 as -2.14748e+09), others as %g. */
static const char *num_text(double v, char *buf, size_t n)
{
    if (v > -1e15 && v < 1e15 && v == (double)(long long)v) /* range first: the cast */
        snprintf(buf, n, "%lld", (long long)v);
    else
        snprintf(buf, n, "%g", v);
    return buf;
}

int hostio_detail_message(const struct actag_error_detail *d, const hostio_optname *map,
                          int nmap, char *err)
{
    const hostio_optname *f, *g;
    const char *name, *other;
    char rule[HOSTIO_ERRLEN];
    double scale;
    char vt[40], lt[40];
    int len;
    if (d == NULL || err == NULL)
        return -1;
    if (d->code == ACTAG_OK || d->field == NULL) {
        snprintf(err, HOSTIO_ERRLEN, "no error");
        return 0;
    }
    f = lookup(map, nmap, d->field);
    g = lookup(map, nmap, d->other);
    name = f ? f->option : d->field;
    other = g ? g->option : d->other;
    scale = f && f->scale != 0.0 ? f->scale : 1.0;
    translate(d->rule ? d->rule : "is invalid", map, nmap, rule, sizeof rule);
    if (d->index >= 0)
        len = snprintf(err, HOSTIO_ERRLEN, "%s: value %d %s (got %s", name, d->index + 1, rule,
                       num_text(d->value * scale, vt, sizeof vt));
    else if (g != NULL && g != f && strcmp(g->option, name) != 0)
        len = snprintf(err, HOSTIO_ERRLEN, "%s/%s: %s (got %s", name, other, rule,
                       num_text(d->value * scale, vt, sizeof vt));
    else
        len = snprintf(err, HOSTIO_ERRLEN, "%s: %s (got %s", name, rule,
                       num_text(d->value * scale, vt, sizeof vt));
    if (len < 0 || len >= HOSTIO_ERRLEN)
        return 0;
    if (d->other != NULL && d->field != NULL && strcmp(d->other, d->field) == 0)
        snprintf(err + len, (size_t)(HOSTIO_ERRLEN - len), " after %s)",
                 num_text(d->limit * scale, lt, sizeof lt));
    else if (d->other != NULL)
        snprintf(err + len, (size_t)(HOSTIO_ERRLEN - len), ", limit %s)",
                 num_text(d->limit * scale, lt, sizeof lt));
    else
        snprintf(err + len, (size_t)(HOSTIO_ERRLEN - len), ")");
    return 0;
}
