/* vorocrust: polyhedral Voronoi meshing from the command line. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "openmp_spin.h"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vorocrust COMMAND [ARGS]\n"
        "commands:\n"
        "  info INPUT          describe a triangle surface (OBJ, OFF, STL, PLY)\n"
        "  voronoi SEEDS.csv   build the conforming Voronoi mesh of seeds\n"
        "  mesh INPUT          VoroCrust: sample a closed surface, place seeds, mesh\n"
        "  quality MESH.vtu    mesh quality report (polyhedra, tetrahedra)\n"
        "  compare INPUT       vorocrust mesh against TetGen on the same surface\n"
        "run 'vorocrust COMMAND --help' for the options of a command\n");
}

int main(int argc, char **argv)
{
    vc_cli_short_openmp_spin(argv);
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "-h") || !strcmp(cmd, "--help") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(cmd, "info"))
        return vc_cmd_info(argc - 1, argv + 1);
    if (!strcmp(cmd, "voronoi"))
        return vc_cmd_voronoi(argc - 1, argv + 1);
    if (!strcmp(cmd, "mesh"))
        return vc_cmd_mesh(argc - 1, argv + 1);
    if (!strcmp(cmd, "quality"))
        return vc_cmd_quality(argc - 1, argv + 1);
    if (!strcmp(cmd, "compare"))
        return vc_cmd_compare(argc - 1, argv + 1);
    fprintf(stderr, "vorocrust: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
