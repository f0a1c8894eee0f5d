from setuptools import find_packages, setup

package_name = 'turtle_square'

setup(
    name=package_name,
    version='0.0.1',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='student',
    maintainer_email='student@example.com',
    description='Moves the turtle in a square path',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'square = turtle_square.square:main',
        ],
    },
)
