"""rospy's handler-return rules and the request-building rules, with their exact texts."""

from __future__ import annotations

from typing import Any

import pytest

from ddes.errors import DdesAttributeError, DdesTypeError, ServiceException
from ddes.msg import get_message_class, get_service_class
from ddes.services.convert import (
    args_kwds_to_request,
    convert_return_to_response,
    roscpp_result,
    server_error_text,
)

SetBool = get_service_class("std_srvs/SetBool")
Empty = get_service_class("std_srvs/Empty")
AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")
TwoInts = get_service_class("roscpp_tutorials/TwoInts")
Resp = AddTwoInts._response_class
Req = AddTwoInts._request_class


class TestConvertReturnToResponse:
    def test_response_instance_is_used_as_it_is(self) -> None:
        resp = Resp(3)
        assert convert_return_to_response(resp, Resp) is resp

    def test_a_message_of_the_same_type_from_another_class_is_used(self) -> None:
        # rospy compares the declared _type, not the class
        other = get_service_class("rospy_tutorials/AddTwoInts")._response_class(4)
        assert convert_return_to_response(other, Resp) is other

    def test_dict_gives_keyword_construction(self) -> None:
        assert convert_return_to_response({"sum": 7}, Resp).sum == 7
        assert convert_return_to_response({}, Resp).sum == 0

    def test_dict_with_unknown_key(self) -> None:
        with pytest.raises(ServiceException) as err:
            convert_return_to_response({"total": 7}, Resp)
        assert str(err.value) == ("handler returned invalid value: total is not an attribute of "
                                  "AddTwoIntsResponse; its fields are sum")

    def test_none(self) -> None:
        with pytest.raises(ServiceException, match=r"^service handler returned None$"):
            convert_return_to_response(None, Resp)

    def test_single_value(self) -> None:
        assert convert_return_to_response(12, Resp).sum == 12

    def test_bare_bool_is_only_valid_for_one_field(self) -> None:
        one = get_message_class("std_msgs/Bool")
        assert convert_return_to_response(True, one).data is True
        with pytest.raises(ServiceException) as err:
            convert_return_to_response(True, SetBool._response_class)
        assert str(err.value) == (
            "handler returned invalid value: Invalid number of arguments, args should be "
            "['success', 'message'] args are(True,); pass all 2 fields in order, or use keyword "
            "arguments")
        with pytest.raises(ServiceException) as err:
            convert_return_to_response(False, Empty._response_class)
        assert str(err.value) == ("handler returned invalid value: Invalid number of arguments, "
                                  "args should be [] args are(False,); EmptyResponse has no fields")

    @pytest.mark.parametrize("value", [(True, "ok"), [True, "ok"]])
    def test_tuple_and_list_are_positional(self, value: Any) -> None:
        resp = convert_return_to_response(value, SetBool._response_class)
        assert (resp.success, resp.message) == (True, "ok")

    @pytest.mark.parametrize("value", [[], (), {}])
    def test_empty_containers_fit_an_empty_response(self, value: Any) -> None:
        assert convert_return_to_response(value, Empty._response_class).__slots__ == ()

    def test_wrong_number_of_values(self) -> None:
        with pytest.raises(ServiceException) as err:
            convert_return_to_response((1, 2), Resp)
        assert str(err.value) == (
            "handler returned wrong number of values: Invalid number of arguments, args should be "
            "['sum'] args are(1, 2); pass all 1 fields in order, or use keyword arguments")

    def test_a_request_is_not_a_response(self) -> None:
        with pytest.raises(ServiceException, match=r"^handler returned invalid value: "):
            convert_return_to_response(Req(1, 2), SetBool._response_class)

    def test_other_containers_are_single_values(self) -> None:
        # only list and tuple are spread (exact type test, as rospy)
        with pytest.raises(ServiceException, match=r"^handler returned invalid value: "):
            convert_return_to_response({1, 2}, Empty._response_class)


class TestServerErrorText:
    def test_rospy_prefixes(self) -> None:
        assert server_error_text(ServiceException("busy"), "rospy") == \
            "service cannot process request: busy"
        assert server_error_text(ValueError("bad"), "rospy") == "error processing request: bad"

    def test_roscpp_sends_the_text_itself(self) -> None:
        assert server_error_text(RuntimeError("what()"), "roscpp") == "what()"

    def test_roscpp_result_needs_a_bool(self) -> None:
        assert roscpp_result(True) is True
        assert roscpp_result(False) is False
        with pytest.raises(DdesTypeError, match="must return True or False"):
            roscpp_result(None)
        with pytest.raises(DdesTypeError, match="got 1"):
            roscpp_result(1)


class TestArgsKwdsToRequest:
    def test_instance_positional_and_keywords(self) -> None:
        req = Req(1, 2)
        assert args_kwds_to_request(Req, (req,), {}) is req
        assert args_kwds_to_request(Req, (3, 4), {}) == Req(3, 4)
        assert args_kwds_to_request(Req, (), {"a": 5, "b": 6}) == Req(5, 6)
        assert args_kwds_to_request(Req, (), {}) == Req(0, 0)

    def test_both_args_and_keywords(self) -> None:
        with pytest.raises(TypeError, match=r"^publish\(\) can be called with arguments or "
                                            r"keywords, but not both\.$"):
            args_kwds_to_request(Req, (1,), {"b": 2})

    def test_another_message_type(self) -> None:
        with pytest.raises(TypeError) as err:
            args_kwds_to_request(Req, (Resp(3),), {})
        assert str(err.value) == "expected [int64] but got [rospy_tutorials/AddTwoIntsResponse]"
        with pytest.raises(TypeError) as err:
            args_kwds_to_request(Empty._request_class, (Resp(3),), {})
        assert str(err.value) == "expected [] but got [rospy_tutorials/AddTwoIntsResponse]"

    def test_same_md5_other_type(self) -> None:
        # roscpp_tutorials/TwoInts has the same fields, so the same md5sum
        other = TwoInts._request_class(1, 2)
        assert other._md5sum == Req._md5sum
        with pytest.raises(TypeError, match=r"^request object type \[.*\] does not match service "
                                            r"type \[.*\]$"):
            args_kwds_to_request(Req, (other,), {})

    def test_wrong_count_and_unknown_keyword(self) -> None:
        with pytest.raises(TypeError, match="Invalid number of arguments"):
            args_kwds_to_request(Req, (1,), {})
        with pytest.raises(DdesAttributeError, match="c is not an attribute of AddTwoIntsRequest"):
            args_kwds_to_request(Req, (), {"c": 1})
