#include "Access/Feedback.h"

namespace armadillo::access {

std::vector<TactileSegment> feedbackSensation(bool right, float level)
{
    if (right) return {{0.0, 0.4, kAllNineMotors, 4.0f, true, false}};
    return {{0.0, 0.1, kOuterMotors, level, false, false},
            {0.2, 0.1, kOuterMotors, level, false, false},
            {0.4, 0.1, kOuterMotors, level, false, false}};
}

} // namespace armadillo::access
