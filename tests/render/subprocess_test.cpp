#include "render/subprocess.h"

#include <gtest/gtest.h>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

TEST(RunProcess, CapturesOutputErrorAndExitCode) {
  const ProcessResult r = run_process({"/bin/sh", "-c", "echo out; echo err >&2; exit 3"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.out, "out\n");
  EXPECT_EQ(r.err, "err\n");
}

TEST(RunProcess, ArgumentsAreNotSplitOrExpanded) {
  const ProcessResult r = run_process({"/bin/echo", "a b", "$HOME", "'q'"});
  EXPECT_EQ(r.out, "a b $HOME 'q'\n");
}

TEST(RunProcess, LargeOutputOnBothStreamsDoesNotBlock) {
  // 1 MB on each stream: more than a pipe buffer (64 kB), so both must be drained together.
  const ProcessResult r =
      run_process({"/bin/sh", "-c", "head -c 1000000 /dev/zero; head -c 1000000 /dev/zero >&2"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.size(), 1000000u);
  EXPECT_EQ(r.err.size(), 1000000u);
}

TEST(RunProcess, MissingProgramThrows) {
  try {
    run_process({"/nonexistent/tool", "x"});
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(),
                 "cannot run '/nonexistent/tool x': No such file or directory (is "
                 "/nonexistent/tool installed and in PATH?)");
  }
}

TEST(TailOf, KeepsTheEndTrimmed) {
  EXPECT_EQ(tail_of("  line 1\nline 2\n\n"), "line 1\nline 2");
  EXPECT_EQ(tail_of("abcdefghij", 4), "...ghij");
}

}  // namespace
}  // namespace chatterlab::render
