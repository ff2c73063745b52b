/* Trees split at the median (a node of count elements has children of
 * count / 2 and count - count / 2, and is a leaf at leaf elements or
 * fewer): the size of a subtree follows from its count alone, so a
 * preorder numbering is known before its left half is built, and the two
 * halves can be built at once (OpenMP tasks) with the same result as one
 * after the other. The sizing's element tree and the Hausdorff check's
 * triangle tree are such. */
#ifndef VC_UTIL_MEDIAN_TREE_H
#define VC_UTIL_MEDIAN_TREE_H

#include <stdint.h>

/* The nodes of a subtree over count elements. */
static inline int64_t vc_median_tree_nodes(int64_t count, int64_t leaf)
{
    if (count <= leaf)
        return 1;
    return 1 + vc_median_tree_nodes(count / 2, leaf) + vc_median_tree_nodes(count - count / 2, leaf);
}

/* Subtrees of more elements than this build their halves as two tasks. */
#define VC_MEDIAN_TREE_TASK 32768

#endif
