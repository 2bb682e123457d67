"""Bad input raises ValueError; a bad material's message is the one the CLI prints after
"gonio: " for the same description, its source named after the Python side (`Material`,
not the command line's `--bsdf`)."""

import numpy as np
import pytest

import gonio
from conftest import run_gonio

BAD_MATERIALS = [
    '{"type":"conductor","eta":-1}',
    '{"type":"nosuchmodel"}',
    '{"type":"roughconductor","material":"Au"}',  # alpha missing
    '{"type":"diffuse","reflectance":[0.5,0.5]}',
    '{"type":"diffuse","colour":0.5}',
    '{"type":"diffuse",',  # malformed JSON
    '{"type":"dielectric","eta":1.5,"eta":2}',  # a key twice
    '[1,2,3]',
    '{"type":"blend","weight":2,"bsdfs":[{"type":"mirror"},{"type":"mirror"}]}',
]


def cli_message(text):
    status, out, err = run_gonio(["eval", "--bsdf", text], "")
    assert status == 2 and out == ""
    assert err.startswith("gonio: ") and err.endswith("\n") and err.count("\n") == 1
    return err[len("gonio: "):-1]


def python_message(cli):
    # The CLI's message with its source, the option --bsdf, named as the Python class.
    assert cli.startswith("--bsdf: "), cli
    return "Material: " + cli[len("--bsdf: "):]


@pytest.mark.parametrize("text", BAD_MATERIALS)
def test_bad_material_raises_the_cli_message(text):
    with pytest.raises(ValueError) as e:
        gonio.Material(text)
    assert str(e.value) == python_message(cli_message(text))
    assert "--bsdf" not in str(e.value)


def test_bad_dict_raises_the_cli_message():
    d = {"type": "roughconductor", "material": "Au", "alpha": 0}
    with pytest.raises(ValueError) as e:
        gonio.Material(d)
    assert str(e.value) == python_message(cli_message('{"type": "roughconductor", "material": "Au", "alpha": 0}'))


def test_error_names_the_python_side_not_the_option():
    # Issue 55: a Python user typed no --bsdf; at a wavelength too, and in gonio.subsurface.
    for kwargs in ({}, {"wavelength": 550}):
        with pytest.raises(ValueError, match=r"^Material: roughconductor: unknown parameter 'alpha_u'"):
            gonio.Material('{"type":"roughconductor","alpha_u":0.3}', **kwargs)
    with pytest.raises(ValueError, match=r"^description: subsurface needs a material of type"):
        gonio.subsurface('{"type":"diffuse"}')


def test_a_good_dict_is_the_same_material_as_its_text():
    d = {"type": "plastic", "reflectance": [0.3, 0.4, 0.5], "alpha": 0.1}
    wo = gonio.direction([10, 40, 70], 0)
    wi = gonio.direction([20, 50, 80], 180)
    np.testing.assert_array_equal(gonio.Material(d).eval(wo, wi)[0],
                                  gonio.Material('{"type":"plastic","reflectance":[0.3,0.4,0.5],"alpha":0.1}')
                                  .eval(wo, wi)[0])


def test_nul_byte_in_material_text_is_refused():
    # The JSON parser took a NUL for the end of the text and ignored what followed it.
    for text in ['{"type":"diffuse"}\x00', '{"type":"diffuse"}\x00{"type":"mirror","x":1}']:
        with pytest.raises(ValueError, match=r"^Material: a NUL byte at byte offset 18 "):
            gonio.Material(text)


def test_wrong_description_type():
    with pytest.raises(ValueError, match="expected JSON text"):
        gonio.Material(3)


m = gonio.Material('{"type":"diffuse"}')


@pytest.mark.parametrize("wo, wi, message", [
    (np.zeros((2, 3)), np.ones((2, 3)), r"^wo\[0\] is a zero vector$"),
    (np.ones((3, 3)), np.array([[1, 1, 1], [0, 0, 1], [np.nan, 0, 1]]), r"^wi\[2\] is not a finite vector$"),
    # A NaN after the first component of a row (it once slipped through as f = 0), in
    # contiguous arrays, a strided view and a single row, and inside a group of four rows.
    (np.ones((3, 3)), np.array([[1, 1, 1], [0, np.nan, 1], [0, 0, 1]]), r"^wi\[1\] is not a finite vector$"),
    (np.array([[0, 0, 1], [0, 1, np.nan]] * 5), np.ones((10, 3)), r"^wo\[1\] is not a finite vector$"),
    (np.ones((6, 3))[::2], np.array([[0, 1, 0], [1, 0, 0], [1, 1, np.nan]]), r"^wi\[2\] is not a finite vector$"),
    (np.array([0, np.nan, 1]), np.ones((4, 3)), r"^wo\[0\] is not a finite vector$"),
    # Rows that need scaling (largest component beyond 2^±500), a NaN after that component.
    (np.array([[1e-300, np.nan, 0]]), np.ones((1, 3)), r"^wo\[0\] is not a finite vector$"),
    (np.ones((5, 3)), np.array([[0, 0, 1]] * 4 + [[1e300, 0, np.nan]]), r"^wi\[4\] is not a finite vector$"),
    (np.ones((2, 2)), np.ones((2, 3)), r"^wo must have shape \(N, 3\) or \(3,\), got \(2, 2\)$"),
    (np.ones((2, 3)), np.ones((3, 3)), "different lengths"),
])
def test_bad_directions(wo, wi, message):
    with pytest.raises(ValueError, match=message):
        m.eval(wo, wi)


def test_the_first_bad_row_is_named_whatever_the_threads():
    wo = np.ones((100000, 3))
    wo[[70000, 99999]] = 0
    for threads in (1, 2):
        with pytest.raises(ValueError, match=r"^wo\[70000\] is a zero vector$"):
            m.eval(wo, wo, threads=threads)


def test_bad_mode_and_u():
    with pytest.raises(ValueError, match="mode must be"):
        m.eval([0, 0, 1], [0, 0, 1], mode="backwards")
    # Issue 39: bytes were taken as the str (pybind11 converts both to std::string).
    for call in (lambda mode: m.eval([0, 0, 1], [0, 0, 1], mode=mode),
                 lambda mode: m.pdf([0, 0, 1], [0, 0, 1], mode=mode),
                 lambda mode: m.sample([0, 0, 1], [0.5, 0.5, 0.5], mode=mode)):
        with pytest.raises(ValueError, match=r"^mode must be the str \"radiance\" or \"importance\", "
                                             r"got b'radiance' \(bytes\)$"):
            call(b"radiance")
        with pytest.raises(ValueError, match=r"got 1 \(int\)$"):
            call(1)
    with pytest.raises(ValueError, match=r"u\[1, 2\] must be in \[0, 1\), got 1"):
        m.sample(np.ones((2, 3)), np.array([[0.1, 0.2, 0.3], [0.1, 0.2, 1.0]]))


@pytest.mark.parametrize("kwargs, args", [
    ({"eta": -2}, ["--eta", "-2"]),
    ({"eta": 1.5, "k": -1}, ["--eta", "1.5", "--k", "-1"]),
    ({"material": "Unobtainium"}, ["--material", "Unobtainium"]),
])
def test_fresnel_errors_are_the_cli_messages(kwargs, args):
    status, _, err = run_gonio(["fresnel", "--theta", "10"] + args)
    assert status == 2
    with pytest.raises(ValueError) as e:
        gonio.fresnel(10.0, **kwargs)
    assert str(e.value) == err[len("gonio: "):-1]


def test_other_errors():
    with pytest.raises(ValueError, match=r"theta must be in \[0, 90\] degrees, got 91"):
        m.albedo(91)
    with pytest.raises(ValueError, match="wavelength must be"):
        gonio.Material('{"type":"diffuse"}', wavelength=1000)
    with pytest.raises(ValueError, match='subsurface needs a material of type "subsurface"'):
        gonio.subsurface('{"type":"diffuse"}')
    if hasattr(gonio, "render"):
        with pytest.raises(ValueError):
            gonio.render("/nonexistent/scene.json")


# The array helpers refuse what has no answer instead of returning NaN or a clamped value.
@pytest.mark.parametrize("call, message", [
    (lambda: gonio.fresnel_dielectric(np.array([0.5, np.nan]), 1.5), r"^cos_i\[1\] must be a cosine in \[-1, 1\], got nan$"),
    (lambda: gonio.fresnel_dielectric(1.1, 1.5), r"^cos_i must be a cosine in \[-1, 1\], got 1\.1$"),
    (lambda: gonio.fresnel_conductor(np.array([-np.inf]), 0.2, 3.0), r"^cos_i\[0\] must be a cosine"),
    (lambda: gonio.fresnel_schlick(np.array([0.1, 0.2, np.nan]), 0.04), r"^cos_i\[2\] must be a cosine"),
    (lambda: gonio.half_diff_directions(np.array([10, np.nan]), 10, 10),
     r"^theta_h\[1\] must be a finite angle in degrees, got nan$"),
    (lambda: gonio.half_diff_directions(10, 10, np.inf), r"^phi_d must be a finite angle in degrees, got inf$"),
    (lambda: gonio.direction(np.array([10, np.nan]), 0), r"^theta\[1\] must be a finite angle in degrees, got nan$"),
    (lambda: gonio.direction(10, np.inf), r"^phi must be a finite angle in degrees, got inf$"),
    (lambda: gonio.spherical(np.array([[0, 0, 1], [0, 0, 0]])), r"^w\[1\] is a zero vector$"),
    (lambda: gonio.spherical([0, np.nan, 1]), r"^w is not a finite vector$"),
    (lambda: gonio.spherical(np.ones((2, 2))), r"^w must have shape \(N, 3\) or \(3,\)"),
])
def test_array_helpers_refuse_bad_values(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_array_helpers_at_their_limits():
    # A cosine a rounding step beyond 1 is 1; directions of any length have their angles.
    assert gonio.fresnel_dielectric(1 + 1e-9, 1.5)[0] == pytest.approx(0.04)
    theta, phi = gonio.spherical(np.array([[1e300, 0, 1e300], [0, 1e-320, 0]]))
    assert theta == pytest.approx([45, 90]) and phi == pytest.approx([0, 90])


@pytest.mark.parametrize("threads", [-1, 1025])
def test_threads_out_of_the_clis_range(threads):
    # As `--threads`: 0 (every core) to 1024.
    message = r"^threads must be an integer from 0 to 1024, got %d$" % threads
    for call in (lambda: m.eval([0, 0, 1], [0, 0, 1], threads=threads),
                 lambda: m.pdf([0, 0, 1], [0, 0, 1], threads=threads),
                 lambda: m.sample([0, 0, 1], [0.5, 0.5, 0.5], threads=threads),
                 lambda: m.albedo(10, samples=16, threads=threads)):
        with pytest.raises(ValueError, match=message):
            call()


def test_sample_with_rows_beyond_memory_fails_at_once():
    """Issue 39: broadcast rows of u were each checked before the outputs failed to
    allocate (10^9 rows: seconds); now sample allocates first, as eval and pdf do, and
    fails at once with numpy's MemoryError naming the size. 10^11 rows (1.1 TiB of wi)
    fail on any machine, where 10^9 (12 GB) might be granted."""
    import time
    u = np.broadcast_to(np.array([0.5, 0.5, 0.5]), (10**11, 3))
    start = time.monotonic()
    with pytest.raises(MemoryError, match="Unable to allocate"):
        m.sample([0, 0, 1], u)
    assert time.monotonic() - start < 1.0
    # A broadcast u is one row: its check costs nothing, a bad value is still named.
    with pytest.raises(ValueError, match=r"u\[0, 1\] must be in \[0, 1\), got 1"):
        m.sample([0, 0, 1], np.broadcast_to(np.array([0.5, 1.0, 0.5]), (10**6, 3)))


def test_tiny_media_are_refused_with_their_range():
    """Issue 39: gonio.subsurface returned infinite radii for sigma ~ 1e-38; the medium is
    now refused with the CLI's message (its documented range)."""
    text = '{"type":"subsurface","sigma_s":1e-38,"sigma_a":1e-38,"method":"diffusion"}'
    status, out, err = run_gonio(["subsurface", "--bsdf", text])
    assert status == 2 and out == ""
    with pytest.raises(ValueError) as e:
        gonio.subsurface(text)
    assert str(e.value) == "description" + err[len("gonio: --bsdf"):-1]
    assert "transport coefficient" in str(e.value)
