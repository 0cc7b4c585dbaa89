// Multi-bounce ambient occlusion (SPEC 1-2): camera rays first, then either one
// work item per pixel that runs the chosen estimator for each of its camera
// samples (the megakernel) or, for the branching estimator, one launch per
// bounce over the surfaces still bouncing (the wavefront), its rays streamed
// through the walk sixteen at a time where the traversal is "lanes".
#include "render/camera_rays.h"
#include "render/ao_estimators.h"
#include "render/wavefront_bounces.h"
#include "render/streamed_bounces.h"
