/* util/number_span.h against the C library: every number vc_strtod_span and
 * vc_strtoll_span read (their exact fast paths included) must give
 * strtod's / strtoll's value, bit for bit, and consume as many characters,
 * on numbers printed every way the readers meet (%.6f, %.9g, %.15g, %.17g,
 * %e, integers), on the boundaries of the fast path (2^53, 10^22, 19
 * digits, leading zeros, signed zeros) and on malformed or glued runs. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/number_span.h"
#include "vorocrust/random.h"

#include "test_check.h"

static int n_checked;

/* s followed by a delimiter, as in a file line */
static void check_double(const char *s)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s x", s);
    double v = -12345.0;
    int erange = -1;
    const size_t n = vc_strtod_span(buf, buf + strlen(buf), &v, &erange);
    char *end;
    errno = 0;
    const double w = strtod(buf, &end);
    const size_t m = (size_t)(end - buf);
    CHECKF(n == m, "'%s': consumed %zu, strtod %zu", s, n, m);
    if (n > 0)
        CHECKF(memcmp(&v, &w, sizeof v) == 0, "'%s': %.17g, strtod %.17g", s, v, w);
    n_checked++;
}

static void check_int(const char *s)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s/", s);
    long long v = -1;
    int erange = -1;
    const size_t n = vc_strtoll_span(buf, buf + strlen(buf), &v, &erange);
    char *end;
    errno = 0;
    const long long w = strtoll(buf, &end, 10);
    const size_t m = (size_t)(end - buf);
    CHECKF(n == m, "'%s': consumed %zu, strtoll %zu", s, n, m);
    if (n > 0)
        CHECKF(v == w, "'%s': %lld, strtoll %lld", s, v, w);
    n_checked++;
}

int main(void)
{
    static const char *cases[] = {
        "0", "-0", "+0", "0.0", "-0.0", ".5", "5.", "-.5e+2", "1e22", "1e23", "1e-22", "1e-23",
        "9007199254740992", "9007199254740993", "9007199254740991.5", "1234567890123456789",
        "12345678901234567890", "0000000000000000000000012.5", "0.000000000000000000000001",
        "4.9e-324", "1e-400", "1e400", "-1.5e", "1.5e+", "1.5e-3-2", "1..5", "--1", "+-1", "e5",
        ".", "-", "inf", "nan", "0x1p3", "1.7976931348623157e308", "2.2250738585072014e-308",
        "3.14159265358979323846", "100000000000000000000000", "123456789e-22", "123456789e-23",
        "0.1", "0.2", "0.3", "1e0", "1E5", "7e+021", "7e-021"};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        check_double(cases[i]);
        check_int(cases[i]);
    }
    static const char *ints[] = {"0", "-1", "+7", "123456789012345678", "1234567890123456789",
                                 "-9223372036854775808", "99999999999999999999", "12a", "1.5"};
    for (size_t i = 0; i < sizeof ints / sizeof *ints; i++)
        check_int(ints[i]);
    vc_rng rng;
    vc_rng_init(&rng, 11, 0);
    static const char *fmt[] = {"%.6f", "%.9g", "%.15g", "%.17g", "%e", "%.3e", "%.12f"};
    char s[128];
    for (int i = 0; i < 200000; i++) {
        /* magnitudes from 1e-30 to 1e30, both signs */
        const double mag = pow(10.0, 60 * vc_rng_uniform(&rng) - 30);
        const double x = (vc_rng_uniform(&rng) < 0.5 ? -1 : 1) * mag * vc_rng_uniform(&rng);
        snprintf(s, sizeof s, fmt[i % (int)(sizeof fmt / sizeof *fmt)], x);
        check_double(s);
        snprintf(s, sizeof s, "%" PRId64, (int64_t)(vc_rng_uniform(&rng) * 1e15) - 500000000000000);
        check_int(s);
    }
    printf("%d numbers checked\n", n_checked);
    return failures != 0;
}
