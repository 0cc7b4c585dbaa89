// The kd-tree walks' numbers (kernels/kd_traversal.h says what each does):
// the kernels' MBAO_TRAVERSAL, and the host's Traversal values
// (render/render_settings.h), one definition for both.
#ifndef MBAO_TRAVERSAL_IDS_H
#define MBAO_TRAVERSAL_IDS_H

#define MBAO_TRAVERSAL_RESTART 0
#define MBAO_TRAVERSAL_PUSHDOWN 1
#define MBAO_TRAVERSAL_SHORT_STACK 2
#define MBAO_TRAVERSAL_STACK 3
#define MBAO_TRAVERSAL_LANES 4

#endif
