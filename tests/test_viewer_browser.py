"""The viewer's page in a real browser (headless Chromium): it loads clean,
follows the mouse and its controls, and shows what render_sequence computes."""

import numpy as np
import pytest
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By

import mbao
from mbao.viewer.session import to_8bit
from viewer_browser import chromium, console_errors, image, set_view, state, wait_for, wait_still
from viewer_client import served


@pytest.fixture(scope="module")
def browser():
    with chromium() as driver:
        yield driver


@pytest.fixture(scope="module")
def viewer():
    with served(width=96, height=80, samples=2, frames=2) as viewer:
        yield viewer


@pytest.fixture
def page(browser, viewer):
    browser.get(viewer.url)
    wait_still(browser)
    return browser


def test_the_page_loads_without_console_errors(page):
    assert console_errors(page) == []
    shown = state(page)
    assert shown["error"] is None and (shown["width"], shown["height"]) == (96, 80)
    assert page.find_element(By.ID, "device").text == mbao.devices()[0].name
    for name in ("bounces", "samples", "rho", "max_distance", "method", "estimator", "denoise", "temporal"):
        assert page.find_element(By.NAME, name), name


def test_a_drag_orbits_the_camera_and_the_image_follows(page):
    before_state, before_image = state(page), image(page)
    ActionChains(page).move_to_element(page.find_element(By.ID, "view")).click_and_hold().move_by_offset(
        30, 0
    ).move_by_offset(30, 5).release().perform()
    after = wait_for(page, lambda s: s["received"] > before_state["received"] and s["final"], "a frame after the drag")
    assert after["camera"]["eye"] != pytest.approx(before_state["camera"]["eye"])
    assert after["camera"]["target"] == pytest.approx(before_state["camera"]["target"])
    assert np.abs(image(page).astype(int) - before_image).mean() > 2


def test_more_bounces_lighten_a_closed_scene(page):
    """Within a radius shorter than the box, b = 2 counts the hits' own openness (SPEC 1)."""
    means = []
    for bounces in (1, 2):
        set_view(page, settings={"bounces": bounces, "max_distance": 150.0, "frames": 2})
        wait_still(page)
        means.append(image(page).mean())
    assert means[1] > means[0] + 5


def test_a_still_view_shows_render_sequences_image(page):
    settings = dict(width=64, height=48, bounces=2, samples=4, rho=0.8, max_distance=200.0)
    set_view(page, settings=dict(settings, frames=3, denoise=True, temporal=True))
    shown = wait_still(page)
    assert shown["frames"] == 3
    camera = mbao.Camera(**shown["camera"])
    *_, last = mbao.render_sequence(mbao.cornell_box(), [camera] * 3, denoise=True, **settings)
    np.testing.assert_array_equal(image(page), to_8bit(last.ao))


def test_a_malformed_message_shows_an_error_and_the_view_goes_on(page):
    page.execute_script('window.mbaoView.sendRaw(\'{"type": "set", "settings": {"bounces": -1.5}}\')')
    shown = wait_for(page, lambda s: s["error"] is not None, "an error")
    assert "bounces must be an integer" in shown["error"]
    assert page.find_element(By.ID, "error").is_displayed()
    received = shown["received"]
    set_view(page, settings={"samples": 3})
    after = wait_for(page, lambda s: s["received"] > received and s["final"], "a frame after the error")
    assert after["error"] is None and not page.find_element(By.ID, "error").is_displayed()


def test_a_control_changes_its_setting(page):
    bounces = page.find_element(By.NAME, "bounces")
    bounces.clear()
    bounces.send_keys("3\n")
    page.find_element(By.NAME, "samples").click()  # the change event comes as the field loses focus
    shown = wait_still(page)
    assert shown["settings"]["bounces"] == 3


def test_two_pages_work_at_once(page, viewer):
    first = page.current_window_handle
    page.switch_to.new_window("tab")
    try:
        page.get(viewer.url)
        wait_still(page)
        home = state(page)["camera"]
        moved = dict(home, eye=[home["eye"][0] + 200, home["eye"][1], home["eye"][2]])
        set_view(page, camera=moved)
        second = wait_still(page)
        second_image = image(page)
        page.switch_to.window(first)
        first_state = wait_still(page)
        assert first_state["camera"]["eye"] != pytest.approx(second["camera"]["eye"])
        assert np.abs(image(page).astype(int) - second_image).mean() > 2
        assert len(viewer.sessions) == 2
    finally:
        page.switch_to.new_window("tab")
        for handle in page.window_handles:
            if handle != first:
                page.switch_to.window(handle)
                page.close()
        page.switch_to.window(first)


def test_a_server_with_a_token_refuses_a_page_without_it(browser):
    with served(width=32, height=32, token="s3cret") as viewer:
        browser.get(f"http://127.0.0.1:{viewer.port}/")
        assert "needs the token" in browser.find_element(By.TAG_NAME, "body").text
        browser.get(viewer.url)
        wait_still(browser)
        assert state(browser)["error"] is None
