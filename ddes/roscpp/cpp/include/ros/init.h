// ddes roscpp: ros::init and the node's life (ok, shutdown, spin, spinOnce).
//
// ros::init connects the process to its ddes world (HELLO, docs/external-nodes.md): the world
// makes the node, resolves its name and namespace with its remappings and the launch file's,
// and answers with them.  As in roscpp, ros::init moves every argument containing ":=" to
// the end of argv and leaves argc counting the others.
#ifndef ROSCPP_INIT_H
#define ROSCPP_INIT_H

#include <string>

#include <ros/forwards.h>
#include <ros/spinner.h>

namespace ros
{

namespace init_options
{
enum InitOption
{
  /// Do not install a SIGINT handler (roscpp's calls ros::requestShutdown()).
  NoSigintHandler = 1 << 0,
  /// Append "_" and the wall-clock nanoseconds to the node's name (ddes's world picks the
  /// suffix deterministically).
  AnonymousName = 1 << 1,
  /// Do not publish log messages on /rosout.
  NoRosout = 1 << 2,
};
}  // namespace init_options
typedef init_options::InitOption InitOption;

void init(int& argc, char** argv, const std::string& name, uint32_t options = 0);
void init(const M_string& remappings, const std::string& name, uint32_t options = 0);
void init(const VP_string& remapping_args, const std::string& name, uint32_t options = 0);

/// Whether ros::init has been called.
bool isInitialized();
/// Whether the node is shutting down (ros::shutdown() called, or the world shut it down).
bool isShuttingDown();

/// Runs the global queue's callbacks until the node shuts down.
void spin();
void spin(Spinner& spinner);
/// Runs the global queue's callbacks that are ready now.
void spinOnce();
/// Waits (on the wall clock) until the node shuts down.
void waitForShutdown();

/// False once the node shut down (or before it started).
bool ok();
/// Shuts the node down: the world withdraws its topics and services.
void shutdown();
/// Asks for a shutdown; it happens soon after (as SIGINT does).
void requestShutdown();

/// Starts the node (the first NodeHandle does this).
void start();
bool isStarted();

CallbackQueue* getGlobalCallbackQueue();

/// The value of a "name:=value" argument, or "".
std::string getROSArg(int argc, const char* const* argv, const std::string& arg);
/// The arguments without those containing ":=".
void removeROSArgs(int argc, const char* const* argv, V_string& args_out);

const std::string& getDefaultMasterURI();

}  // namespace ros

#endif  // ROSCPP_INIT_H
