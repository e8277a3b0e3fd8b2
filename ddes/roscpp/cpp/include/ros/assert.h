// ddes roscpp: ROS_ASSERT and friends (rosconsole's assert.h, minimal).
//
// Enabled unless NDEBUG is defined (or always, with ROS_ASSERT_ENABLED), as in ROS.  A failed
// assertion prints rosconsole's text on stderr and stops the process with a breakpoint trap
// (the world then reports the node's death).  ROS_STATIC_ASSERT/ROS_COMPILE_ASSERT are
// static_assert.
#ifndef ROSCONSOLE_ROSASSERT_H
#define ROSCONSOLE_ROSASSERT_H

#include <cstdio>
#include <cstdlib>

#ifndef ROS_COMPILE_ASSERT
#define ROS_COMPILE_ASSERT(cond) static_assert(cond, #cond)
#endif
#ifndef ROS_STATIC_ASSERT
#define ROS_STATIC_ASSERT(cond) static_assert(cond, #cond)
#endif

#if defined(__i386__) || defined(__x86_64__)
#define ROS_ISSUE_BREAK() asm("int $3");
#else
#define ROS_ISSUE_BREAK() std::abort();
#endif

#ifndef NDEBUG
#ifndef ROS_ASSERT_ENABLED
#define ROS_ASSERT_ENABLED
#endif
#endif

#ifdef ROS_ASSERT_ENABLED
#define ROS_BREAK() \
  do { \
    std::fprintf(stderr, "[FATAL] BREAKPOINT HIT\n\tfile = %s\n\tline=%d\n", __FILE__, __LINE__); \
    std::fflush(stderr); \
    ROS_ISSUE_BREAK() \
  } while (false)

#define ROS_ASSERT(cond) \
  do { \
    if (!(cond)) { \
      std::fprintf(stderr, "[FATAL] ASSERTION FAILED\n\tfile = %s\n\tline = %d\n\tcond = %s\n", \
                   __FILE__, __LINE__, #cond); \
      std::fflush(stderr); \
      ROS_ISSUE_BREAK() \
    } \
  } while (false)

#define ROS_ASSERT_MSG(cond, ...) \
  do { \
    if (!(cond)) { \
      std::fprintf(stderr, "[FATAL] ASSERTION FAILED\n\tfile = %s\n\tline = %d\n\tcond = %s\n\tmessage = ", \
                   __FILE__, __LINE__, #cond); \
      std::fprintf(stderr, __VA_ARGS__); \
      std::fprintf(stderr, "\n"); \
      std::fflush(stderr); \
      ROS_ISSUE_BREAK() \
    } \
  } while (false)

#define ROS_ASSERT_CMD(cond, cmd) \
  do { \
    if (!(cond)) { \
      cmd; \
    } \
  } while (false)
#else
#define ROS_BREAK()
#define ROS_ASSERT(cond)
#define ROS_ASSERT_MSG(cond, ...)
#define ROS_ASSERT_CMD(cond, cmd)
#endif

#endif  // ROSCONSOLE_ROSASSERT_H
