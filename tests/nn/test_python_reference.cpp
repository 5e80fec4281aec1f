// training/pllvo_nets (the PyTorch SuperPoint and LightGlue that pllvo trains) against the
// official reference vectors, through training/check_nets.py.
#include <gtest/gtest.h>

#include "nn_test_util.h"

namespace pllvo::nn {
namespace {

TEST(PythonReferenceNets, ReproduceOfficialVectors) {
  const auto& python = test::python_with_torch();
  ASSERT_FALSE(python.empty()) << "no python3 with torch (Debian: python3-torch); set PLLVO_PYTHON";
  std::string log;
  const int status = test::run_command("OMP_NUM_THREADS=1 " + python + " " + std::string(PLLVO_SOURCE_DIR) +
                                           "/training/check_nets.py --shared " + shared_dir().string(),
                                       log);
  EXPECT_EQ(status, 0) << log;
  EXPECT_NE(log.find("all checks passed"), std::string::npos) << log;
  EXPECT_EQ(log.find("FAIL"), std::string::npos) << log;
}

}  // namespace
}  // namespace pllvo::nn
