"""The facade's index: every name it offers resolves, is documented where it is defined, and
is the one its module defines; type checkers see the same names as the index."""

import ast
import importlib
import inspect

import pytest

import lotsim.api
from conftest import ROOT


@pytest.mark.parametrize("name", lotsim.api.__all__)
def test_each_name_is_its_module_s_and_documented(name):
    module = importlib.import_module(lotsim.api.EXPORTS_BY_NAME[name])
    value = getattr(lotsim.api, name)
    assert value is getattr(module, name)
    if inspect.isfunction(value) or inspect.isclass(value):
        assert inspect.getdoc(value), name


def test_type_checkers_see_the_names_of_the_index():
    tree = ast.parse((ROOT / "lotsim" / "api" / "__init__.py").read_text())
    guarded = next(node for node in tree.body if isinstance(node, ast.If)
                   and ast.unparse(node.test) == "TYPE_CHECKING")
    seen = {(imp.module, alias.name) for imp in guarded.body for alias in imp.names}
    index = {(module, name) for module, names in lotsim.api.EXPORTS.items() for name in names}
    assert seen == index


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        lotsim.api.nothing  # noqa: B018
