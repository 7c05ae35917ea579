// Linked into every test of a ThreadSanitizer build (MOSTAR_SANITIZE=thread): OpenCV's TBB thread
// pool is not instrumented, so TSan cannot see its synchronisation and reports races inside
// OpenCV (cv::Canny, cv::parallel_for_). OpenCV then runs on the calling thread; mostar's own
// threads (edge worker, camera pipeline, DDS callbacks, control loop) are still checked.
#include <opencv2/core/utility.hpp>

namespace {
const int kOpenCvSerial = (cv::setNumThreads(0), 0);
}  // namespace
