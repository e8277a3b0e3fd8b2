// ddes roscpp: rosconsole's severity levels.
#ifndef ROSCONSOLE_CONSOLE_BACKEND_H
#define ROSCONSOLE_CONSOLE_BACKEND_H

namespace ros
{
namespace console
{
namespace levels
{
enum Level
{
  Debug,
  Info,
  Warn,
  Error,
  Fatal,

  Count
};
}  // namespace levels
typedef levels::Level Level;
}  // namespace console
}  // namespace ros

#endif  // ROSCONSOLE_CONSOLE_BACKEND_H
