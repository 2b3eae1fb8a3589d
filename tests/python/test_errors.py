"""Bad input raises the named exceptions, with the CLI's messages, and changes nothing."""
import numpy as np
import pytest

from conftest import SCENES

SCENE = SCENES / "truss_bridge.yaml"


@pytest.fixture(scope="module")
def scene(ispars):
    return ispars.Scene.load(str(SCENE))


def test_an_unknown_method_or_variant_names_the_field(ispars, scene):
    with pytest.raises(ispars.InputError) as e:
        ispars.Builder(scene, method="prm")
    assert (e.value.file, e.value.field) == ("build", "method")
    assert str(e.value) == "build: method: 'prm' is not one of dense, spars, ispars, irisc, ispars2"
    with pytest.raises(ispars.InputError, match="variant: 'alg1' given, but dense has no rule-set variants"):
        ispars.Builder(scene, method="dense", variant="alg1")
    assert isinstance(e.value, ValueError)


@pytest.mark.parametrize("overrides, field", [
    ({"dense_delta": -1.0}, "overrides.dense_delta"),
    ({"p_accept": 2.0}, "overrides.p_accept"),
    ({"stretch": float("nan")}, "overrides.stretch"),
    ({"sparse_delta": 1e5}, "overrides.sparse_delta"),
    ({"stretch_slack_after": 1.5}, "overrides.stretch_slack_after"),
    ({"warp": 1.0}, "overrides.warp"),
])
def test_an_out_of_range_parameter_names_it(ispars, scene, overrides, field):
    with pytest.raises(ispars.InputError) as e:
        ispars.Builder(scene, overrides=overrides)
    assert e.value.field == field, str(e.value)


@pytest.mark.parametrize("kwargs, message", [
    (dict(method="dense", overrides={"stretch_slack": 0.5}),
     "overrides.stretch_slack: 0.5 given, but dense method has no stretch rules to slacken"),
    (dict(method="ispars", overrides={"stretch_slack_after": 100}),
     "overrides.stretch_slack_after: 100 given, but there is no stretch_slack to start there"),
    (dict(method="spars", overrides={"stretch": 150}), "overrides.stretch: must be in [1, 100], got 150"),
    (dict(method="ispars", overrides={"stretch_slack_after": 2.5}),
     "overrides.stretch_slack_after: must be a whole number in [0, 1000000000000], got 2.5"),
    (dict(method="ispars", overrides={"stretch_slack_after": -1}),
     "overrides.stretch_slack_after: must be a whole number in [0, 1000000000000], got -1"),
    (dict(method="irisc", variant="alg1"),
     "variant: 'alg1' given, but irisc has no rule-set variants (spars and ispars have)"),
])
def test_a_builder_refuses_what_the_daemon_refuses_in_its_words(ispars, scene, kwargs, message):
    # The daemon's words for the same requests: tests/integration/test_service.cpp and
    # tests/cli/test_lab_requests.cpp, all from make_recipe.
    with pytest.raises(ispars.InputError) as e:
        ispars.Builder(scene, **kwargs)
    assert message in str(e.value)


def test_overrides_by_keyword_are_the_declared_parameters(ispars, scene):
    declared = ispars.recipe_parameters()
    assert [p["name"] for p in declared] == ["dense_delta", "sparse_delta", "stretch", "stretch_slack",
                                             "stretch_slack_after", "p_accept"]
    after = next(p for p in declared if p["name"] == "stretch_slack_after")
    assert after["type"] == "int" and after["range"] == "a whole number in [0, 1000000000000]"
    by_keyword = ispars.Builder(scene, method="ispars2", stretch_slack=0.25, stretch_slack_after=100)
    by_dict = ispars.Builder(scene, method="ispars2", overrides={"stretch_slack": 0.25, "stretch_slack_after": 100})
    assert by_keyword.recipe == by_dict.recipe
    assert by_keyword.recipe["stretch_slack_after"] == 100 and isinstance(by_keyword.recipe["stretch_slack_after"], int)
    with pytest.raises(ispars.InputError, match="overrides.stretch: given twice"):
        ispars.Builder(scene, overrides={"stretch": 1.5}, stretch=2.0)
    with pytest.raises(ispars.InputError, match="overrides.warp: unknown parameter"):
        ispars.Builder(scene, warp=1.0)
    with pytest.raises(ispars.InputError, match="overrides.stretch_slack_after: expected a number, got True"):
        ispars.Builder(scene, stretch_slack=0.5, stretch_slack_after=True)
    # Keywords of one call never reach the next (the overrides default is one dict for every call).
    assert ispars.Builder(scene).recipe == ispars.Builder(scene, overrides={}).recipe
    assert ispars.Builder(scene).recipe["stretch_slack"] == 0.0


def test_counts_out_of_range_are_refused(ispars, scene):
    with pytest.raises(ispars.InputError, match=r"threads: must be a whole number in \[1, 64\], got 0"):
        ispars.Builder(scene, threads=0)
    builder = ispars.Builder(scene)
    for samples in (0, -5, 2**53 + 1):
        with pytest.raises(ispars.InputError, match=r"samples: must be a whole number in \[1, 9007199254740992\]"):
            builder.extend(samples)
    assert builder.samples == 0 and builder.roadmap.vertex_count == 1  # the root alone: nothing changed
    with pytest.raises(ispars.InputError, match=r"tour: budget: must be in \(0, 3600\], got 0"):
        ispars.tour(builder.roadmap, budget=0)
    with pytest.raises(ispars.InputError, match="tour: threads"):
        ispars.tour(builder.roadmap, threads=65)
    with pytest.raises(ispars.InputError, match="tour: targets: -1 is not a POI id"):
        ispars.tour(builder.roadmap, targets=[-1])
    with pytest.raises(ispars.InputError, match="render: width"):
        ispars.render(scene, width=3)


def test_a_missing_or_broken_file_names_it(ispars, tmp_path):
    with pytest.raises(ispars.InputError) as e:
        ispars.Scene.load(str(tmp_path / "none.yaml"))
    assert e.value.file == str(tmp_path / "none.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("mesh: [unclosed\n")
    with pytest.raises(ispars.InputError, match="bad.yaml"):
        ispars.Scene.load(str(bad))
    with pytest.raises(ispars.InputError, match="cannot be read"):
        ispars.load_roadmap(str(tmp_path / "none.json"))
    broken = tmp_path / "broken.json"
    broken.write_text('{"graphs": {"roadmap": {"vertices": [[0, 0, 0]], "visible": [], "edges": []}}}')
    with pytest.raises(ispars.InputError, match="visible"):
        ispars.load_roadmap(str(broken))
    with pytest.raises(ispars.InputError, match="graph: 'sparse' is not one of roadmap, dense"):
        ispars.load_roadmap(str(broken), "sparse")


def test_a_tour_for_pois_not_seen_names_the_targets(ispars, scene):
    builder = ispars.Builder(scene)
    builder.extend(2000)
    with pytest.raises(ispars.InputError) as e:
        ispars.tour(builder.roadmap, iterations=10, targets=[10**6])
    assert (e.value.file, e.value.field) == ("tour", "targets")


def test_points_must_be_three_numbers(ispars, scene):
    with pytest.raises(ValueError, match="point: expected three numbers"):
        scene.point_valid([1, 2])
    assert isinstance(scene.point_valid(np.array([0.0, -12.0, 1.5])), bool)


def test_a_client_with_no_daemon_raises_no_daemon(ispars, domain):
    client = ispars.Client(domain=domain, timeout=1.0)
    with pytest.raises(ispars.ClientError) as e:
        client.stats("truss_bridge")
    assert e.value.kind == "no_daemon", str(e.value)
    with pytest.raises(ispars.InputError, match=r"client: domain: must be a whole number in \[0, 232\], got 300"):
        ispars.Client(domain=300)
    with pytest.raises(ispars.InputError, match="client: timeout"):
        ispars.Client(domain=domain, timeout=0)


def test_paths_may_be_pathlike_and_a_builder_takes_a_scene_file(ispars, tmp_path):
    scene = ispars.Scene.load(SCENE)  # a pathlib.Path
    builder = ispars.Builder(SCENE, method="ispars", seed=5)
    assert builder.scene.name == scene.name
    builder.extend(500)
    path = tmp_path / "r.json"
    builder.roadmap.save(path, scene.name, scene.root, scene.pois)
    assert ispars.load_roadmap(path).vertex_count == builder.roadmap.vertex_count
    assert ispars.render(scene, roadmap=builder.roadmap, width=32, height=24, path=tmp_path / "r.png").shape == (24, 32, 3)
    with pytest.raises(ispars.InputError) as e:
        ispars.Builder(42)
    assert (e.value.file, e.value.field) == ("build", "scene")


@pytest.mark.parametrize("make, field", [
    (lambda i, s: i.Builder(s, seed=-1), "seed"),
    (lambda i, s: i.Builder(s, seed=2**64), "seed"),
    (lambda i, s: i.Builder(s, seed=1.5), "seed"),
    (lambda i, s: i.Builder(s, threads=0), "threads"),
    (lambda i, s: i.Builder(s, threads=True), "threads"),
    (lambda i, s: i.Builder(s).extend(2**64), "samples"),
    (lambda i, s: i.Builder(s).extend(0), "samples"),
    (lambda i, s: i.Builder(s).extend(10.0), "samples"),
])
def test_bad_whole_numbers_are_input_errors_not_type_errors(ispars, scene, make, field):
    with pytest.raises(ispars.InputError) as e:
        make(ispars, scene)
    assert (e.value.file, e.value.field) == ("build", field), str(e.value)


def test_the_package_has_a_version_and_says_what_it_was_built_with(ispars):
    assert isinstance(ispars.__version__, str) and ispars.__version__.count(".") == 2
    assert isinstance(ispars.HAS_CLIENT, bool)
    if ispars.HAS_CLIENT:
        assert ispars.Client is not None


def test_an_extend_past_the_memory_limit_is_refused_before_it_starts(ispars, scene):
    small = ispars.Builder(scene, method="dense", memory_mb=16)
    cost = small.expected_cost(10_000_000)
    assert cost["memory_limit"] == 16 * 2**20 and cost["bytes"] > cost["memory_limit"], cost
    with pytest.raises(ispars.InputError, match=r"samples: the roadmap would hold about .* after 10000000 more "
                                                r"samples, past this Builder's memory limit of 16 MiB"):
        small.extend(10_000_000)
    assert small.samples == 0, "refused before any sample was drawn"
    assert small.extend(200) == 200, "what fits is drawn"
    default = ispars.Builder(scene)
    assert default.expected_cost(0)["memory_limit"] >= 2**30, "half of this machine's memory"
    for bad in (-1, 2**30 + 1, 1.5):
        with pytest.raises(ispars.InputError) as e:
            ispars.Builder(scene, memory_mb=bad)
        assert e.value.field == "memory_mb", str(e.value)
