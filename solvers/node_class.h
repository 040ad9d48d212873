// The classes of a graph node in one handle layout (paper §5): what the
// solvers vary. Totally Free varies R and t, Half Free R only, Fixed nothing
// (its values stay as given): a Fixed node's blocks, and a Half Free node's
// translation, are constant blocks. scales/node_classes.h decides them.

#ifndef MSDEFORM_SOLVERS_NODE_CLASS_H_
#define MSDEFORM_SOLVERS_NODE_CLASS_H_

namespace msdeform {

enum class NodeClass { kFixed = 0, kHalfFree = 1, kTotallyFree = 2 };

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_NODE_CLASS_H_
