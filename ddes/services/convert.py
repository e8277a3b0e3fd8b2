"""The value rules of ROS services: handler returns, call arguments, error texts.

Pure functions, no simulation: what rospy's ``convert_return_to_response``
does with a handler's return value, what roscpp does with a ``bool``
callback, and how ``ServiceProxy.call(*args, **kwds)`` builds its request
(``rospy.msg.args_kwds_to_message``).  Each raises with rospy's text, so an
autograder can compare the strings a client sees with real ROS.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import cast

from ddes.errors import DdesError, DdesTypeError, ServiceException
from ddes.msg.message import Message

__all__ = [
    "ERROR_PROCESSING",
    "ROSCPP_EXCEPTION_LOG",
    "SERVICE_CANNOT_PROCESS",
    "args_kwds_to_request",
    "check_service_class",
    "convert_return_to_response",
    "roscpp_result",
    "server_error_text",
]

#: Prefix of the error a client sees when the handler raised ServiceException (rospy).
SERVICE_CANNOT_PROCESS = "service cannot process request: "
#: Prefix of the error a client sees when the handler raised anything else (rospy).
ERROR_PROCESSING = "error processing request: "
#: What roscpp logs (ROS_ERROR) when a service callback throws.
ROSCPP_EXCEPTION_LOG = "Exception thrown while processing service call: %s"


def check_service_class(service_class: object, what: str) -> None:
    """Raise DdesTypeError unless ``service_class`` is a generated service class."""
    if not isinstance(service_class, type) or not all(
        hasattr(service_class, a) for a in ("_type", "_md5sum", "_request_class", "_response_class")
    ):
        raise DdesTypeError(
            f"{what}: service_class must be a service class (e.g. "
            f"get_service_class('rospy_tutorials/AddTwoInts')), got {service_class!r}"
        )


def convert_return_to_response(response: object, response_class: type[Message]) -> Message:
    """A handler's return value as a response message, by rospy's rules, in order.

    1. a message whose ``_type`` is the response type is used as it is;
    2. a ``dict`` gives ``Resp(**d)``; an unknown key raises
       ``ServiceException("handler returned invalid value: ...")``;
    3. ``None`` (compared with ``==``, as rospy) raises
       ``ServiceException("service handler returned None")``;
    4. any value that is not a ``list``/``tuple`` gives ``Resp(x)``; a
       TypeError becomes ``"handler returned invalid value: ..."``;
    5. a ``list``/``tuple`` gives ``Resp(*x)``; a TypeError becomes
       ``"handler returned wrong number of values: ..."``.

    So a bare ``True`` is a valid return only when the response has exactly
    one field (genpy's constructor needs one positional value per field).
    """
    tp = type(response)
    if tp is response_class:
        return cast(Message, response)
    if tp is int or tp is float or tp is str or tp is bool:  # Resp(x), as rule 4 (never None)
        try:
            return response_class(response)
        except TypeError as exc:
            raise ServiceException(f"handler returned invalid value: {exc}") from None
    if isinstance(response, Message) and response._type == response_class._type:
        return response
    if type(response) is dict:
        try:
            return response_class(**response)
        except AttributeError as exc:
            raise ServiceException(f"handler returned invalid value: {exc}") from None
    if response == None:  # noqa: E711 - rospy compares with ==, not is
        raise ServiceException("service handler returned None")
    if type(response) is not list and type(response) is not tuple:
        try:
            return response_class(response)
        except TypeError as exc:
            raise ServiceException(f"handler returned invalid value: {exc}") from None
    try:
        return response_class(*response)  # a list or a tuple here
    except TypeError as exc:
        raise ServiceException(f"handler returned wrong number of values: {exc}") from None


def server_error_text(exc: BaseException, style: str) -> str:
    """The error string a server sends back for a handler exception.

    rospy: ``"service cannot process request: <e>"`` for ServiceException,
    ``"error processing request: <e>"`` for anything else.  roscpp sends the
    exception's text (``e.what()``) as it is.
    """
    if style == "roscpp":
        return str(exc)
    if isinstance(exc, ServiceException):
        return SERVICE_CANNOT_PROCESS + str(exc)
    return ERROR_PROCESSING + str(exc)


def roscpp_result(value: object) -> bool:
    """A roscpp callback's return value as the ok flag; only a bool is accepted.

    C++ forces ``bool``; in Python a callback that forgets ``return True``
    returns None, which ddes reports instead of guessing.
    """
    if value is True or value is False:
        return value
    raise DdesTypeError(
        f"a roscpp-style service callback must return True or False (bool), got {value!r}; "
        "fill the response argument and return True on success"
    )


def args_kwds_to_request(request_class: type[Message], args: tuple[object, ...],
                         kwds: Mapping[str, object]) -> Message:
    """The request of ``proxy(*args, **kwds)``, by rospy's rules and texts.

    A request instance (same md5sum and type), positional field values, or
    keyword field values.  Wrong usage raises TypeError (DdesTypeError) with
    rospy's wording: both args and keywords; another message type
    (``"expected [<first field type>] but got [<type>]"``, as
    ``rospy.msg.args_kwds_to_message``); the same md5sum but another type
    (``"request object type [...] does not match service type [...]"``).
    """
    if args and kwds:
        raise DdesTypeError("publish() can be called with arguments or keywords, but not both.")
    request: object
    if kwds:
        request = request_class(**kwds)
    elif len(args) == 1 and getattr(args[0], "_md5sum", None) == request_class._md5sum:
        request = args[0]
    else:
        if len(args) == 1 and isinstance(args[0], Message):
            slot_types = list(request_class._slot_types)
            if not slot_types:
                raise DdesTypeError(f"expected [] but got [{args[0]._type}]")
            if args[0]._type != slot_types[0]:
                raise DdesTypeError(f"expected [{slot_types[0]}] but got [{args[0]._type}]")
        try:
            request = request_class(*args)
        except DdesError:
            raise
        except TypeError as exc:
            raise DdesTypeError(str(exc)) from None
    if not isinstance(request, Message):
        raise DdesTypeError("request object is not a valid request message instance")
    if request._type != request_class._type:
        raise DdesTypeError(
            f"request object type [{type(request)}] does not match service type [{request_class}]")
    return request
