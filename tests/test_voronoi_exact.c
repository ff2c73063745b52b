/* The Voronoi engine tests of test_voronoi.c, run on the exact engine
 * (vc_voronoi_options.exact; issue 19). */
#define VC_TEST_EXACT_ENGINE 1
#include "test_voronoi.c"
