// One contact as the core takes it (contacts.hpp): rows 3 (point) or 6 (frame), the frame index, the reference
// code (frames.hpp), the damping gain K_d. Its own header so that the batched kernels' arguments (groups.hpp)
// name the one type every instruction set's translation unit shares.
#pragma once

namespace fdcore {

struct ContactSpec {
  int rows, frame, ref;
  double kd;
};

}  // namespace fdcore
