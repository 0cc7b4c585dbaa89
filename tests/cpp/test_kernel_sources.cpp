#include <gtest/gtest.h>

#include "opencl/kernel_sources.h"

namespace mbao {
namespace {

TEST(KernelSources, EveryProgramAndHeaderIsEmbedded) {
  const auto& files = embedded_kernel_files();
  for (const char* name : {"render.cl", "trace.cl", "kd_traversal.h", "mbao/kd_node.h", "mbao/philox.h"})
    EXPECT_TRUE(files.count(name)) << name;
}

TEST(KernelSources, IncludesAreExpandedOnceEach) {
  const std::string source = kernel_program_source("render.cl");
  EXPECT_EQ(source.find("#include \""), std::string::npos);
  // kd_node.h reaches render.cl through several headers but appears once.
  const std::string guard = "#define MBAO_KD_NODE_H";
  const auto first = source.find(guard);
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(source.find(guard, first + 1), std::string::npos);
  EXPECT_NE(source.find("__kernel void trace_camera_rays"), std::string::npos);
}

TEST(KernelSources, UnknownNamesAreAProgrammingError) {
  EXPECT_THROW(kernel_program_source("no_such_kernel.cl"), std::logic_error);
}

}  // namespace
}  // namespace mbao
